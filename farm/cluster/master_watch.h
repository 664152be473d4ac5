#pragma once
/// A worker's watch on rank 0. Rank 0 says it runs several times a second (kTagAlive, also while
/// it loads the scene); a worker gives it up when
/// - it can see rank 0's process has ended (rank 0 on the same machine: process_identity.h):
///   a second later (rank 0's last words already sent, a stop, or mpirun ending the job after
///   rank 0's MPI_Abort, come first);
/// - rank 0 has been silent for `silence` seconds (`firstWord` before rank 0's first word): a
///   rank 0 on another machine, dead or cut off, or one that hangs.
/// A stop of this process (the whole job paused: Ctrl-Z, a Slurm suspend) is not rank 0's silence.
#include <chrono>
#include <stdexcept>
#include <string>

#include "farm/cluster/liveness.h"
#include "farm/cluster/transport.h"

namespace rf::farm {

/// Thrown where a worker waits for rank 0 outside its loop (the scene broadcast) and gives it
/// up; the line saying why was printed. The worker must leave at once (_Exit): MPI_Finalize
/// would wait for rank 0 forever.
class MasterLost : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class MasterWatch {
public:
    using Clock = std::chrono::steady_clock;
    MasterWatch(const Transport& t, double silence, double firstWord);
    /// A message from rank 0 came.
    void heard(Clock::time_point now);
    /// This process was stopped since the last look: rank 0's clock starts again.
    void notePause(Clock::time_point now);
    /// Judged after the messages that came are read: "" while rank 0 counts as running, else
    /// the error line saying why this worker stops (printed by the caller).
    std::string lost(Clock::time_point now);

private:
    const Transport& t_;
    double silence_, firstWord_;
    Clock::time_point lastHeard_, lastLook_{}, endedSeen_{};
    bool heardOnce_ = false;
    bool ended_ = false;
    PauseDetector pause_;
};

/// "rank 2 on node3": where a message comes from when ranks span hosts.
std::string whoAmI(const Transport& t);

}  // namespace rf::farm
