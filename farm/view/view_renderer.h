#pragma once
/// The viewer's renderer: a thread that renders the latest requested view with renderTile on
/// all local cores. While the camera moves it renders 1 spp (at a lower resolution when a frame
/// takes too long); at rest it refines in passes of 1, 4, 16, ... spp up to the target, the last
/// pass being exactly what `still` renders. A new request cancels the work in flight between
/// tiles. No window system here: results go to a callback as 8-bit RGB.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "scene.h"
#include "timeline.h"

namespace rf::view {

using Clock = std::chrono::steady_clock;

/// What to show: the camera (or the timeline's own camera) at a frame of the timeline.
struct ViewRequest {
    Camera camera;
    int frame = 0;
    bool moving = false;          ///< 1 spp, reduced resolution allowed
    bool followTimeline = false;  ///< use the timeline's camera at `frame`, not `camera`
    std::optional<Clock::time_point> input;  ///< the input event this view answers, for latency
};

/// A picture for the window: full passes, and partial ones while a slow pass renders.
struct ViewFrame {
    uint64_t epoch = 0;
    int width = 0, height = 0;  ///< of rgb; smaller than the target while moving at low resolution
    std::vector<uint8_t> rgb;   ///< width × height × 3, toRgb8 of the linear tiles
    std::vector<uint8_t> tileRank;  ///< rank that rendered each 32×32 tile of the target size (row-major)
    int spp = 0;                ///< samples per pixel of this pass
    bool complete = false;      ///< the whole pass is in rgb
    bool final = false;         ///< complete at the target spp: nothing more will come for this view
    bool moving = false;
    double passMs = 0.0;        ///< render time of the pass so far
    Camera camera;              ///< the camera rendered (the timeline's when following it)
    int frame = 0;
    std::optional<Clock::time_point> input;
};

class ViewRenderer {
public:
    using Publish = std::function<void(ViewFrame&&)>;
    static constexpr int kTile = 32;

    /// settings: the target picture (size, spp, depth ...); threads 0 = all cores.
    ViewRenderer(Scene scene, anim::Timeline timeline, RenderSettings settings, int threads, Publish publish);
    ~ViewRenderer();
    ViewRenderer(const ViewRenderer&) = delete;
    ViewRenderer& operator=(const ViewRenderer&) = delete;

    /// Replaces whatever is pending or rendering; returns the request's epoch.
    uint64_t request(const ViewRequest& r);
    /// The error that stopped the render thread, empty while all is well.
    std::string error() const;
    const RenderSettings& settings() const { return settings_; }
    int threads() const { return threads_; }
    /// Plays another timeline from the next request on, over the scene as loaded.
    void setTimeline(const anim::Timeline& tl);

private:
    void loop();
    /// Renders one pass; false when a newer request cancelled it.
    bool renderPass(const ViewRequest& r, const Camera& cam, uint64_t epoch, int spp, int scale, ViewFrame& frame);
    bool cancelled(uint64_t epoch) const { return epoch_.load() != epoch; }

    const Scene pristine_;  ///< as loaded: a new timeline starts from it, not from another's pose
    Scene scene_;
    anim::Timeline timeline_;
    std::optional<anim::Timeline> pendingTimeline_;
    RenderSettings settings_;
    int threads_;
    Publish publish_;
    int appliedFrame_ = -1;
    int scale_ = 1;  ///< moving frames render at 1/scale of the target size

    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<ViewRequest> pending_;
    std::atomic<uint64_t> epoch_{0};
    bool stop_ = false;
    std::string error_;
    std::thread thread_;
};

/// spp of the refinement passes at rest: n = 1, 2, 4, ... up to √target, always ending at target.
std::vector<int> refinementSpp(int targetSpp);

}  // namespace rf::view
