#include "farm/cluster/master_watch.h"

#include <cstdio>

#include <unistd.h>

namespace rf::farm {

namespace {

/// How often a worker looks at rank 0's process (a read of /proc/PID/stat).
constexpr double kLookSeconds = 0.1;
/// How long a worker still listens after rank 0's process ended: a stop it sent just before
/// it left is already on its way (shared memory or a socket keeps it), and wins; and a rank 0
/// that ended the job itself (MPI_Abort: a lost display, a lost worker under plain mpirun) has
/// mpirun end this rank within moments, without a second error line from it.
constexpr double kLastWordsSeconds = 1.0;

double seconds(MasterWatch::Clock::duration d) { return std::chrono::duration<double>(d).count(); }

}  // namespace

std::string whoAmI(const Transport& t) {
    char host[256] = {};
    ::gethostname(host, sizeof host - 1);
    return "rank " + std::to_string(t.rank()) + " on " + host;
}

MasterWatch::MasterWatch(const Transport& t, double silence, double firstWord)
    : t_(t), silence_(silence), firstWord_(firstWord), lastHeard_(Clock::now()) {}

void MasterWatch::heard(Clock::time_point now) {
    lastHeard_ = now;
    heardOnce_ = true;
}

void MasterWatch::notePause(Clock::time_point now) {
    if (pause_.resumed(now)) lastHeard_ = now;
}

std::string MasterWatch::lost(Clock::time_point now) {
    notePause(now);
    if (!ended_ && seconds(now - lastLook_) >= kLookSeconds) {
        lastLook_ = now;
        if (t_.processEnded(0)) {
            ended_ = true;
            endedSeen_ = now;
        }
    }
    char line[512];
    if (ended_ && seconds(now - endedSeen_) > kLastWordsSeconds) {
        std::snprintf(line, sizeof line, "rayfarm: error: %s: rank 0's process has ended (killed or crashed); this worker stops\n",
                      whoAmI(t_).c_str());
        return line;
    }
    const double silent = seconds(now - lastHeard_);
    if (silent <= (heardOnce_ ? silence_ : firstWord_)) return {};
    std::snprintf(line, sizeof line,
                  "rayfarm: error: %s: rank 0 has been silent for %.1f s (stopped, or its host cut off); this worker stops\n",
                  whoAmI(t_).c_str(), silent);
    return line;
}

}  // namespace rf::farm
