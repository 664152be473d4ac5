#include "farm/cluster/launcher_reaper.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <linux/close_range.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace rf::farm {

namespace {

// The reaper is forked from a multi-threaded process: until it ends it may only make plain
// system calls (no allocation, no stdio), so these work on fixed buffers.

bool isMpirun(const char* commPath) {
    char comm[32] = {};
    const int fd = ::open(commPath, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const ssize_t n = ::read(fd, comm, sizeof comm - 1);
    ::close(fd);
    if (n <= 0) return false;
    comm[n - 1] = comm[n - 1] == '\n' ? '\0' : comm[n - 1];
    return std::strcmp(comm, "mpirun") == 0 || std::strcmp(comm, "orterun") == 0 || std::strcmp(comm, "mpiexec") == 0;
}

double now() {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// The reaper keeps nothing of rank 0 open: a socket or pipe it held would make mpirun think
/// rank 0 is still there.
void dropInheritedFiles() {
    const int devNull = ::open("/dev/null", O_RDWR);
    for (int fd = 0; fd < 3; ++fd) ::dup2(devNull, fd);
    if (::syscall(SYS_close_range, 3u, ~0u, 0u) == 0) return;
    for (int fd = 3; fd < 4096; ++fd) ::close(fd);  // kernels before 5.9
}

}  // namespace

void armLauncherReaper(double seconds) {
    const pid_t launcher = ::getppid();
    char commPath[64];
    std::snprintf(commPath, sizeof commPath, "/proc/%d/comm", int(launcher));
    if (!isMpirun(commPath)) return;
    const pid_t child = ::fork();
    if (child != 0) return;  // rank 0 goes on (or fork failed: nothing to do)
    // Out of rank 0's session and process group, so that mpirun's kill of rank 0 misses it.
    ::setsid();
    dropInheritedFiles();
    const double end = now() + seconds;
    const timespec tick{0, 100 * 1000 * 1000};
    while (now() < end) {
        if (::kill(launcher, 0) != 0 || !isMpirun(commPath)) ::_exit(0);  // mpirun ended by itself
        ::nanosleep(&tick, nullptr);
    }
    if (isMpirun(commPath)) ::kill(launcher, SIGKILL);
    ::_exit(0);
}

}  // namespace rf::farm
