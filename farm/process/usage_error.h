#pragma once
/// Bad usage: a wrong option, an output that cannot be written, a frames directory that does not
/// match the run. The command prints "rayfarm: error: <what()>" and exits with status 2, as for
/// an engine InputError.
#include <stdexcept>

namespace rf {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace rf
