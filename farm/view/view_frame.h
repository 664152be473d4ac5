#pragma once
/// A view to render (camera, frame, moving or at rest) and a picture of it for the window.
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "engine/scene/scene.h"
#include "anim/timeline.h"

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

/// Side of the square cells ViewFrame::tileRank describes.
inline constexpr int kTintTile = 32;

/// Where a backend hands its pictures (any thread).
using Publish = std::function<void(ViewFrame&&)>;

/// spp of the refinement passes at rest: n = 1, 2, 4, ... up to √target, always ending at target.
std::vector<int> refinementSpp(int targetSpp);

/// What a moving frame may take: about two of them pass between an input and its picture.
inline constexpr double kMovingFrameMs = 20.0;

/// Divisor of the target size for the next moving frame: halves the resolution when a frame
/// took over kMovingFrameMs, and doubles it back when the next size up (4× the pixels) would
/// still take under 3/4 of it. 1, 2 or 4.
int nextMovingScale(int scale, double frameMs);

/// The moving frames' scale over a drag: down at once when a frame overran (nextMovingScale),
/// but up only after a run of frames that all say so, a run twice as long after each step up
/// that the next frame undid. A step up costs one frame of 4× the pixels; made on one fast
/// frame it made the resolution flicker and put those slow frames in the latency's 95th
/// percentile.
class MovingScale {
public:
    static constexpr int kFirstRun = 8, kLongestRun = 128;
    int scale() const { return scale_; }
    /// A moving frame rendered at scale() took frameMs; returns the scale of the next one.
    int next(double frameMs);

private:
    int scale_ = 1;
    int fastRun_ = 0;  ///< frames in a row that would step up
    int needed_ = kFirstRun;
    bool justUp_ = false;
};

}  // namespace rf::view
