#pragma once
/// The last second before SIGKILL. mpirun follows its SIGTERM with SIGKILL about a second later;
/// rank 0 spends it finishing the video. But the main thread may be held inside an MPI call
/// then: Open MPI 4.1 reports a broken TCP connection to a peer by waiting, inside MPI, for
/// mpirun to print the report, and mpirun is busy killing the job. SignalDeadline watches from
/// its own thread: if a signal arrived and the main thread has not taken the wind-down over
/// within the grace time, it runs `lastWords` itself and ends the process with its result.
#include <atomic>
#include <functional>
#include <thread>

namespace rf::farm {

class SignalDeadline {
public:
    SignalDeadline(double graceSeconds, std::function<int()> lastWords);
    ~SignalDeadline();
    SignalDeadline(const SignalDeadline&) = delete;
    SignalDeadline& operator=(const SignalDeadline&) = delete;
    /// The main thread takes the wind-down over. False if the watchdog already has: the process
    /// is about to end, and the caller must leave the outputs alone (waitForEnd).
    bool claim();
    /// Blocks until the watchdog ends the process.
    [[noreturn]] void waitForEnd();

private:
    void watch(double graceSeconds);
    std::function<int()> lastWords_;
    std::atomic<bool> claimed_{false}, stop_{false};
    std::thread thread_;
};

}  // namespace rf::farm
