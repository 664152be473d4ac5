#include "farm/output/run_stats.h"

#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "engine/util/file_write.h"
#include "farm/output/output_check.h"
#include "farm/process/version.h"

namespace rf {

void writeStatsJson(const std::string& path, const RunStats& s) {
    nlohmann::ordered_json j;
    j["version"] = farm::rayfarmVersion();
    j["frames"] = s.frames;
    j["width"] = s.width;
    j["height"] = s.height;
    j["mode"] = s.mode;
    j["ranks"] = s.ranks;
    j["threads_per_rank"] = s.threadsPerRank;
    j["wall_s"] = s.wallSeconds;
    j["sustained_fps"] = s.sustainedFps;
    j["render_s"] = s.renderSeconds;
    j["encode_s"] = s.encodeSeconds;
    nlohmann::ordered_json rays;
    for (const RayCounter& c : kRayCounters) rays[c.name] = s.rays.*c.field;
    rays["total"] = s.rays.total();
    j["rays"] = rays;
    nlohmann::ordered_json ranks = nlohmann::ordered_json::array();
    for (const RankStats& r : s.perRank)
        ranks.push_back({{"rank", r.rank}, {"busy_s", r.busySeconds}, {"frames", r.frames}, {"tiles", r.tiles}});
    j["per_rank"] = ranks;
    if (!s.lostWorkers.empty()) {
        nlohmann::ordered_json lost = nlohmann::ordered_json::array();
        for (const RunStats::LostRank& l : s.lostWorkers)
            lost.push_back({{"rank", l.rank}, {"host", l.host}, {"at_s", l.atSeconds}, {"doing", l.doing}, {"requeued", l.requeued}});
        j["lost_workers"] = lost;
    }
    for (const auto& [k, v] : s.extra) j[k] = v;
    for (const auto& [k, v] : s.extraText) j[k] = v;
    const std::string text = j.dump(2) + "\n";
    writeReplacing(path, [&](const std::string& to) { writeFileChecked(to, text); });  // never half a stats file
}

}  // namespace rf
