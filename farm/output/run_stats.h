#pragma once
/// The --stats JSON file (fields as in docs/architecture.md; add fields, never rename).
#include <map>
#include <string>
#include <vector>

#include "engine/util/stats.h"

namespace rf {

struct RankStats {
    int rank = 0;
    double busySeconds = 0.0;
    int frames = 0;
    int tiles = 0;
};

struct RunStats {
    int frames = 0;
    int width = 0, height = 0;
    std::string mode = "still";
    int ranks = 1;
    int threadsPerRank = 1;
    double wallSeconds = 0.0;
    double sustainedFps = 0.0;
    double renderSeconds = 0.0;
    double encodeSeconds = 0.0;
    RayStats rays;
    std::vector<RankStats> perRank;
    /// Workers given up on during the run (their work went to the others): written as
    /// "lost_workers" when there are any.
    struct LostRank {
        int rank = 0;
        std::string host;
        double atSeconds = 0.0;  ///< since rendering started
        std::string doing, requeued;
    };
    std::vector<LostRank> lostWorkers;
    std::map<std::string, double> extra;  ///< further numeric fields, written as they are named
    std::map<std::string, std::string> extraText;
};

/// Writes stats as JSON; throws std::runtime_error naming the path on failure.
void writeStatsJson(const std::string& path, const RunStats& s);

}  // namespace rf
