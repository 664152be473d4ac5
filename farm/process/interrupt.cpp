#include "farm/process/interrupt.h"

#include <atomic>
#include <cerrno>
#include <csignal>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/util/load_control.h"

namespace rf::farm {

namespace {
std::atomic<int> gSignal{0};
std::atomic<pid_t> gLauncher{0};       ///< the parent followed (followLauncher), 0 if none
std::atomic<int> gLauncherStderr{-1};  ///< its stderr, opened while it ran
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need a lock-free flag");

extern "C" void onSignal(int sig) {
    gSignal.store(sig);
    requestLoadCancel(sig);  // a load in progress stops at its next poll (load_control.h)
}

void noteStderrFailure(int err) {
    // The first signal wins: a broken pipe after SIGHUP is part of the same hang-up.
    int none = 0;
    if (err == EPIPE && gSignal.compare_exchange_strong(none, SIGPIPE)) requestLoadCancel(SIGPIPE);
}


/// Where the user reads this process's lines: mpirun's own stderr once mpirun has gone (this
/// process's stderr was a pipe to it), else stderr.
int stderrTarget() {
    const int launcherErr = gLauncherStderr.load();
    const pid_t launcher = gLauncher.load();
    if (launcherErr >= 0 && launcher != 0 && ::getppid() != launcher) return launcherErr;
    return STDERR_FILENO;
}

bool sameFile(int a, int b) {
    struct stat sa {}, sb {};
    return ::fstat(a, &sa) == 0 && ::fstat(b, &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}
}  // namespace

void followLauncher(bool keepItsStderr) {
    const pid_t parent = ::getppid();
    if (parent <= 1) return;
    if (keepItsStderr && gLauncherStderr.load() < 0) {
        // Not blocking at the open: a FIFO with no reader would wait for one.
        const std::string path = "/proc/" + std::to_string(parent) + "/fd/2";
        int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
        if (fd >= 0 && sameFile(fd, STDERR_FILENO)) {  // no forwarding in between: nothing to keep
            ::close(fd);
            fd = -1;
        }
        if (fd >= 0) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
        gLauncherStderr.store(fd);
        // That may be a terminal whose foreground group this process is not in: with `stty
        // tostop` a write there would stop it (SIGTTOU) instead of printing its last lines.
        struct sigaction ign {};
        ign.sa_handler = SIG_IGN;
        sigemptyset(&ign.sa_mask);
        ::sigaction(SIGTTOU, &ign, nullptr);
    }
    gLauncher.store(parent);
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) onSignal(SIGTERM);  // it ended before the request was made
}

void ignoreWriteSignals() {
    struct sigaction ign {};
    ign.sa_handler = SIG_IGN;
    sigemptyset(&ign.sa_mask);
    sigaction(SIGXFSZ, &ign, nullptr);
    sigaction(SIGPIPE, &ign, nullptr);
}

void installInterruptHandlers() {
    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGHUP, &sa, nullptr);
    ignoreWriteSignals();
}

void restoreDefaultSignals() {
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &dfl, nullptr);
    if (const int sig = gSignal.load(); sig == SIGINT || sig == SIGTERM || sig == SIGHUP) ::raise(sig);
}

int interruptSignal() { return gSignal.load(); }

void raiseInterrupt(int sig) {
    gSignal.store(sig);
    requestLoadCancel(sig);
}

std::string signalName(int sig) {
    switch (sig) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        case SIGHUP: return "SIGHUP";
        case SIGPIPE: return "SIGPIPE";
        default: return "signal " + std::to_string(sig);
    }
}

bool writeStderrText(const std::string& text) {
    size_t done = 0;
    int fd = stderrTarget();
    while (done < text.size()) {  // a pipe may take a long line in parts; EINTR retries
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int err = n < 0 ? errno : EIO;
            // mpirun has just gone (the pipe broke before its death reached us): to its stderr.
            if (fd == STDERR_FILENO && (err == EPIPE || err == EIO) && gLauncherStderr.load() >= 0) {
                fd = gLauncherStderr.load();
                continue;
            }
            noteStderrFailure(err);
            return false;
        }
        done += size_t(n);
    }
    return true;
}


}  // namespace rf::farm
