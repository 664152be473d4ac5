#pragma once
/// Bad usage: a wrong option, an output that cannot be written, a frames directory that does not
/// match the run. The command prints "rayfarm: error: <what()>" and exits with status 2, as for
/// an engine InputError.
#include <stdexcept>
#include <string>

#include "engine/util/errors.h"

namespace rf {

class UsageError : public std::runtime_error {
public:
    /// The message as printable() makes it: names typed by the user reach the terminal escaped.
    explicit UsageError(const std::string& message) : std::runtime_error(printable(message)) {}
};

}  // namespace rf
