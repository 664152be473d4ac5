#pragma once
/// Errors in user input: they name the file (and, inside it, the element) that is wrong.
#include <stdexcept>
#include <string>
#include <string_view>

namespace rf {

/// Text from a user's file or command line made safe for one line of a terminal: control
/// characters (a newline, NUL, ESC that would start an escape sequence, C1 controls) become
/// \n, \r, \t or \u00XX as JSON writes them, bytes that are not UTF-8 become \xNN; everything
/// else is kept. Backslashes are kept as they are: the result is for reading, not for parsing.
std::string printable(std::string_view text);

/// Bad input: the CLI prints "rayfarm: error: <what()>" and exits with status 2. The message
/// is printable(): keys and names from the file cannot cut it short (a NUL) or reach the
/// terminal raw.
class InputError : public std::runtime_error {
public:
    InputError(const std::string& file, const std::string& message)
        : std::runtime_error(printable(file) + ": " + printable(message)), file_(file) {}
    const std::string& file() const { return file_; }

private:
    std::string file_;
};

}  // namespace rf
