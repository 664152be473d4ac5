#include "farm/output/output_check.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

#include "farm/process/usage_error.h"

namespace rf {

void checkWritableFile(const std::string& path) {
    const bool existed = ::access(path.c_str(), F_OK) == 0;
    if (existed && std::filesystem::is_directory(path)) throw UsageError(path + ": cannot write: is a directory");
    // Opening a FIFO for writing waits for a reader, for good if none comes; a socket cannot be
    // opened at all. Devices (/dev/null, /dev/full) are written in place.
    struct stat st {};
    if (existed && ::stat(path.c_str(), &st) == 0 && (S_ISFIFO(st.st_mode) || S_ISSOCK(st.st_mode)))
        throw UsageError(path + ": cannot write: is " + (S_ISFIFO(st.st_mode) ? "a FIFO" : "a socket") +
                         ", not a regular file (an output is written as a file; name one)");
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

void writeReplacing(const std::string& path, const std::function<void(const std::string&)>& write) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
        write(path);
        return;
    }
    // Beside the file the link points to, so the rename stays in one file system and the link stays.
    std::error_code ec;
    std::string target = path;
    if (std::filesystem::is_symlink(path, ec)) {
        const auto resolved = std::filesystem::canonical(path, ec);
        if (!ec) target = resolved.string();
    }
    const std::string tmp = target + ".part-" + std::to_string(::getpid());
    try {
        write(tmp);
    } catch (const std::exception& e) {
        ::unlink(tmp.c_str());
        std::string what = e.what();
        if (what.rfind(tmp, 0) == 0) what = path + what.substr(tmp.size());  // the user's name, not ours
        throw std::runtime_error(what);
    } catch (...) {
        ::unlink(tmp.c_str());
        throw;
    }
    if (::rename(tmp.c_str(), target.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        throw std::runtime_error(path + ": cannot write: " + std::strerror(err));
    }
}

}  // namespace rf
