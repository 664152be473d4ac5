#include "output_check.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <unistd.h>

#include "usage_error.h"

namespace rf {

void checkWritableFile(const std::string& path) {
    const bool existed = ::access(path.c_str(), F_OK) == 0;
    if (existed && std::filesystem::is_directory(path)) throw UsageError(path + ": cannot write: is a directory");
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT, 0644);
    if (fd < 0) throw UsageError(path + ": cannot write: " + std::strerror(errno));
    ::close(fd);
    if (!existed) ::unlink(path.c_str());
}

void ensureWritableDir(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) throw UsageError(dir + ": cannot create directory: " + ec.message());
    if (::access(dir.c_str(), W_OK) != 0) throw UsageError(dir + ": cannot write: " + std::strerror(errno));
}

}  // namespace rf
