#pragma once
/// Interactive frames through the farm: runFarm with FarmOptions::views renders the views a
/// caller (the viewer's window) posts to a ViewInbox, on every rank of the transport, until the
/// cancel flag, a signal or a lost rank ends the session. Each pass of a view is an epoch of its
/// own: rank 0 sends its ViewSpec (camera, size, spp: kTagView) to every rank, then its work
/// items stamped with the epoch; a newer view makes every rank drop older work, the item being
/// rendered included, and rank 0 drops late results of older epochs. The workers are the
/// farm's own (runWorker over a RenderEngine), so a pass is the frame `still` renders with that
/// camera and spp, pixel for pixel.
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "engine/geometry/camera.h"
#include "engine/integrators/render.h"

namespace rf::farm {

/// One pass of a view: its picture size and samples per pixel.
struct ViewPass {
    int spp = 1, width = 1, height = 1;
};

/// A view to render: its passes in order (e.g. 1, 4, 16 spp at rest; one small 1 spp pass
/// while the camera moves), each delivered whole, until a newer view replaces it.
struct ViewOrder {
    uint64_t id = 0;  ///< the caller's name for it, given back with its pictures
    int frame = 0;
    bool followTimeline = false;  ///< the timeline's camera at frame, not `camera`
    Camera camera;
    std::vector<ViewPass> passes;
};

/// A rendered rectangle of a pass picture and the rank that rendered it (the viewer's tint).
struct ViewTile {
    TileRect rect;
    int rank = 0;
};

/// What FarmProgress::view says of the picture in FarmProgress::rgb.
struct ViewPicture {
    uint64_t id = 0;  ///< its ViewOrder's
    int pass = 0, passes = 1;
    ViewPass size;
    /// false: a slow pass's picture so far (every 150 ms); only the pixels of `tiles` are rendered
    bool complete = false;
    double ms = 0.0;  ///< render time of the pass so far
    const std::vector<ViewTile>* tiles = nullptr;  ///< the rectangles rendered so far
};

/// Where the caller posts views; thread-safe. A posted view replaces one not yet started and
/// cancels the one rendering.
class ViewInbox {
public:
    void post(ViewOrder v) {
        std::lock_guard<std::mutex> lock(mutex_);
        next_ = std::move(v);
    }
    bool pending() const {
        std::lock_guard<std::mutex> lock(mutex_);
        return next_.has_value();
    }
    std::optional<ViewOrder> take() {
        std::lock_guard<std::mutex> lock(mutex_);
        std::optional<ViewOrder> v = std::move(next_);
        next_.reset();
        return v;
    }

private:
    mutable std::mutex mutex_;
    std::optional<ViewOrder> next_;
};

struct RenderJob;
struct SharedScene;
struct FarmOptions;
struct FarmOutcome;
class Transport;

/// runFarm's interactive session (run_farm.h): job.settings is the picture every pass renders
/// (with the pass's size and spp), job.workerTimeout how long a rank may stay silent. The
/// workers stay in their loops when it returns, unless FarmOptions::keepWorkers is false.
FarmOutcome runViewSession(Transport& t, const RenderJob& job, SharedScene& shared, const FarmOptions& opts);

}  // namespace rf::farm
