#include "farm/view/view_stats.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace rf::view {

void ViewStats::frameShown(double nowS, bool moving, double latencyMs, int width) {
    ++frames_;
    if (latencyMs >= 0.0) latencies_.push_back(latencyMs);
    if (!moving) return;
    ++movingFrames_;
    ++movingWidths_[width];
    if (lastMovingS_ >= 0.0 && nowS - lastMovingS_ < 0.5) {
        movingSeconds_ += nowS - lastMovingS_;
        ++movingIntervals_;
    }
    lastMovingS_ = nowS;
}

double ViewStats::movingFps() const {
    // Frames per second within motions: the first frame of a motion opens no interval.
    return movingSeconds_ > 0.0 ? movingIntervals_ / movingSeconds_ : 0.0;
}

double ViewStats::latencyMeanMs() const {
    if (latencies_.empty()) return 0.0;
    return std::accumulate(latencies_.begin(), latencies_.end(), 0.0) / double(latencies_.size());
}

double ViewStats::latencyP95Ms() const {
    if (latencies_.empty()) return 0.0;
    std::vector<double> v = latencies_;
    std::sort(v.begin(), v.end());
    const size_t rank = static_cast<size_t>(std::ceil(0.95 * double(v.size())));
    return v[std::max<size_t>(rank, 1) - 1];
}

void ViewStats::write(const std::string& path, int width, int height, int ranks, int threads) const {
    nlohmann::json j;
    j["frames_shown"] = frames_;
    j["moving_frames"] = movingFrames_;
    j["moving_fps"] = movingFps();
    nlohmann::json widths = nlohmann::json::object();
    for (auto [w, n] : movingWidths_) widths[std::to_string(w)] = n;
    j["moving_frames_by_width"] = widths;
    j["latency_samples"] = latencies_.size();
    j["latency_mean_ms"] = latencyMeanMs();
    j["latency_p95_ms"] = latencyP95Ms();
    j["width"] = width;
    j["height"] = height;
    j["ranks"] = ranks;
    j["threads_per_rank"] = threads;
    std::ofstream f(path);
    f << j.dump(2) << "\n";
    if (!f) throw std::runtime_error(path + ": cannot write the stats file");
}

}  // namespace rf::view
