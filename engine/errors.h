#pragma once
/// Errors in user input: they name the file (and, inside it, the element) that is wrong.
#include <stdexcept>
#include <string>

namespace rf {

/// Bad input: the CLI prints "rayfarm: error: <what()>" and exits with status 2.
class InputError : public std::runtime_error {
public:
    InputError(const std::string& file, const std::string& message)
        : std::runtime_error(file + ": " + message), file_(file) {}
    const std::string& file() const { return file_; }

private:
    std::string file_;
};

}  // namespace rf
