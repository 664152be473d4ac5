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

#include "view_backend.h"

namespace rf::view {

class ViewRenderer : public ViewBackend {
public:
    static constexpr int kTile = kTintTile;

    /// settings: the target picture (size, spp, depth ...); threads 0 = all cores.
    ViewRenderer(Scene scene, anim::Timeline timeline, RenderSettings settings, int threads, Publish publish);
    ~ViewRenderer();
    ViewRenderer(const ViewRenderer&) = delete;
    ViewRenderer& operator=(const ViewRenderer&) = delete;

    uint64_t request(const ViewRequest& r) override;
    std::string error() const override;
    int threads() const override { return threads_; }
    void setTimeline(const anim::Timeline& tl, const std::string& timelineJson) override;

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


}  // namespace rf::view
