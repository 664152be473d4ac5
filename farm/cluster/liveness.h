#pragma once
/// Telling "the other side went silent" from "I was not running". A loop that checks a peer's
/// last message against a timeout also watches its own rhythm: when its own iterations stall
/// for longer than kPausedSeconds (SIGSTOP, Ctrl-Z, a Slurm suspend, a VM pause), the silence it
/// then sees is its own, and every peer's clock starts again.
#include <chrono>

namespace rf::farm {

/// A loop that runs every few milliseconds never stalls this long unless it was stopped.
inline constexpr double kPausedSeconds = 2.0;

class PauseDetector {
public:
    using Clock = std::chrono::steady_clock;
    /// True if this is the first call after a stall of more than kPausedSeconds (the steady
    /// clock keeps counting while a process is stopped).
    bool resumed(Clock::time_point now) {
        const bool gap = last_ != Clock::time_point{} && std::chrono::duration<double>(now - last_).count() > kPausedSeconds;
        last_ = now;
        return gap;
    }

private:
    Clock::time_point last_{};
};

}  // namespace rf::farm
