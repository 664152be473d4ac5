#include "farm/process/signal_deadline.h"

#include <chrono>
#include <cstdlib>

#include "farm/process/interrupt.h"

namespace rf::farm {

SignalDeadline::SignalDeadline(double graceSeconds, std::function<int()> lastWords)
    : lastWords_(std::move(lastWords)), thread_([this, graceSeconds] { watch(graceSeconds); }) {}

SignalDeadline::~SignalDeadline() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
}

bool SignalDeadline::claim() { return !claimed_.exchange(true); }

void SignalDeadline::waitForEnd() {
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
}

void SignalDeadline::watch(double graceSeconds) {
    using Clock = std::chrono::steady_clock;
    Clock::time_point signalled{};
    while (!stop_ && !claimed_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (!interruptSignal()) continue;
        const auto now = Clock::now();
        if (signalled == Clock::time_point{}) signalled = now;
        if (std::chrono::duration<double>(now - signalled).count() < graceSeconds) continue;
        if (!claim()) return;  // the main thread got there first
        int code = 1;
        try {
            code = lastWords_();
        } catch (...) {
            // Leave all the same: SIGKILL is coming.
        }
        std::_Exit(code);
    }
}

}  // namespace rf::farm
