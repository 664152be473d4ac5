#include "interrupt.h"

#include <atomic>
#include <cerrno>
#include <csignal>

#include <unistd.h>

namespace rf::farm {

namespace {
std::atomic<int> gSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need a lock-free flag");

extern "C" void onSignal(int sig) { gSignal.store(sig); }

void noteStderrFailure(int err) {
    // The first signal wins: a broken pipe after SIGHUP is part of the same hang-up.
    int none = 0;
    if (err == EPIPE) gSignal.compare_exchange_strong(none, SIGPIPE);
}
}  // namespace

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

int interruptSignal() { return gSignal.load(); }

void raiseInterrupt(int sig) { gSignal.store(sig); }

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
    while (done < text.size()) {  // a pipe may take a long line in parts; EINTR retries
        const ssize_t n = ::write(STDERR_FILENO, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            noteStderrFailure(n < 0 ? errno : EIO);
            return false;
        }
        done += size_t(n);
    }
    return true;
}


}  // namespace rf::farm
