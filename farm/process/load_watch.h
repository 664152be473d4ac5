#pragma once
/// Ctrl-C, SIGTERM or a hang-up while the scene loads ends the run within a second, with one
/// line saying so. The handlers (interrupt.h) stop the engine's loaders at their next poll
/// (engine/util/load_control.h), which throw LoadCancelled; the command catches it and calls
/// LoadWatch::interrupted. A third-party parser (tinygltf, nlohmann) or an MPI call cannot poll:
/// if the load has not stopped kGraceSeconds after the signal, the watch's own thread says the
/// same line and ends the process (SignalDeadline), as mpirun's SIGKILL would a second later.
#include <functional>
#include <string>

#include "engine/util/load_control.h"
#include "farm/process/signal_deadline.h"

namespace rf::farm {

/// "rayfarm: interrupted (SIGTERM) while loading FILE (building the BVH); nothing was rendered\n"
std::string loadInterruptedLine(int sig, const std::string& file, const std::string& step);

class LoadWatch {
public:
    /// How long a load may go on after a signal before the watch ends the process itself.
    /// Short: what comes after it (the line, freeing a large scene's memory at exit) must fit in
    /// the second as well, on a machine that is busy.
    static constexpr double kGraceSeconds = 0.3;
    /// The same for a rank that ends quietly (a worker): longer, so that rank 0 has said its
    /// line first. mpirun kills every rank the moment one of them ends, and a worker whose
    /// watch fired at the same 0.3 s as rank 0's (both held in a step that cannot poll) took
    /// the line with it in about one Ctrl-C of three. Still well inside mpirun's second.
    static constexpr double kQuietGraceSeconds = 0.6;

    /// file: what is being loaded, for the line. speak: this process tells the user (rank 0;
    /// the others end quietly). beforeExit: on the watch's thread, just before the process
    /// ends (release the output locks).
    LoadWatch(std::string file, bool speak, std::function<void()> beforeExit = {});
    /// The load is over and the command goes on: from here the command's own wind-down answers
    /// signals. If the watch is already ending the process, waits for that instead.
    void done();
    /// For the command's catch of LoadCancelled: says the line (unless the watch already did)
    /// and returns the exit status, 128 + the signal.
    int interrupted(const LoadCancelled& c);

private:
    int lastWords();

    std::string file_;
    bool speak_;
    std::function<void()> beforeExit_;
    SignalDeadline deadline_;
};

}  // namespace rf::farm
