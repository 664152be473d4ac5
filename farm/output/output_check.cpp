#include "farm/output/output_check.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/util/file_source.h"
#include "farm/process/usage_error.h"

namespace rf {

void ensureParentDir(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (parent.empty()) return;
    std::error_code ec;
    if (std::filesystem::is_directory(parent, ec)) return;
    // As Blender does: the folders an output names are made. A part of the way that is a file,
    // or a folder that may not be written, refuses the output naming the folder.
    std::filesystem::create_directories(parent, ec);
    if (!ec && std::filesystem::is_directory(parent)) return;
    // The reason as the user can act on it: which part of the way is not a folder.
    std::string why = ec ? ec.message() : std::string("a file is in the way");
    for (std::filesystem::path up = parent; !up.empty() && up != up.parent_path(); up = up.parent_path()) {
        std::error_code e;
        if (std::filesystem::exists(up, e) && !std::filesystem::is_directory(up, e)) {
            why = up.string() + " is " + (notRegularFile(up.string()).empty() ? std::string("a file") : notRegularFile(up.string())) +
                  ", not a folder";
            break;
        }
    }
    throw UsageError(parent.string() + ": cannot create the folder for " + path + ": " + why);
}

void checkWritableFile(const std::string& path) {
    ensureParentDir(path);
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
    if (ec || !std::filesystem::is_directory(dir))
        throw UsageError(dir + ": cannot create the folder: " + (ec ? ec.message() : std::string("a file is in the way")));
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
