#include "interrupt.h"

#include <atomic>
#include <csignal>

namespace rf::farm {

namespace {
std::atomic<int> gSignal{0};
static_assert(std::atomic<int>::is_always_lock_free, "signal handlers need a lock-free flag");

extern "C" void onSignal(int sig) { gSignal.store(sig); }
}  // namespace

void installInterruptHandlers() {
    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESTART;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

int interruptSignal() { return gSignal.load(); }

void raiseInterrupt(int sig) { gSignal.store(sig); }

}  // namespace rf::farm
