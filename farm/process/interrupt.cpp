#include "farm/process/interrupt.h"

#include <atomic>
#include <cerrno>
#include <csignal>

#include <unistd.h>

#include "engine/util/load_control.h"

namespace rf::farm {

namespace {
std::atomic<int> gSignal{0};
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
