#include "engine/util/file_write.h"

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

namespace rf {

namespace {
[[noreturn]] void fail(const std::string& path, int err) {
    throw std::runtime_error(path + ": cannot write: " + std::strerror(err));
}
}  // namespace

void writeFileChecked(const std::string& path, std::string_view bytes, bool sync) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) fail(path, errno);
    size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int err = n < 0 ? errno : ENOSPC;
            ::close(fd);
            fail(path, err);
        }
        done += size_t(n);
    }
    // Devices and pipes cannot be synced (EINVAL/EROFS); their write errors came from write().
    if (sync && ::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        const int err = errno;
        ::close(fd);
        fail(path, err);
    }
    if (::close(fd) != 0 && errno != EINTR) fail(path, errno);
}

}  // namespace rf
