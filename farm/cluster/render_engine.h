#pragma once
/// One rank's renderer: a thread that takes work items in order, sets the scene to the item's
/// frame through the timeline, and renders the item's rectangle with all the rank's threads
/// (the rectangle split into sub-tiles). Small items of one frame waiting in its queue are
/// rendered together, so tiles smaller than the threads' share still keep every thread busy.
/// The rank's main thread stays free for messages.
/// Items of the epoch the engine's ViewSpec names (WorkItem::epoch) render as it says; a new
/// ViewSpec drops the work of every other epoch, the item being rendered included.
#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "farm/cluster/messages.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"
#include "anim/timeline.h"

namespace rf::farm {

class RenderEngine {
public:
    /// Renders a job's item in place of tracing it (given the 8-bit plane's channels): a
    /// benchmark's stand-in work (bench_free_work.h). Never used for a viewer's epochs.
    using ItemRenderer = std::function<TileResult(const WorkItem&, int channels)>;

    /// threads: render threads for this rank (≥ 1). linear: results carry the linear plane too
    /// (PixelLayout), for EXR frames. itemRenderer: null (trace the scene) but in benchmarks.
    /// bounceSlot: the job's bounce cache (SharedScene::bounceSlot), which a head start may
    /// have filled; null: one of the engine's own. Kept across setScene.
    RenderEngine(Scene scene, anim::Timeline timeline, RenderSettings settings, int threads, bool linear = false,
                 ItemRenderer itemRenderer = nullptr, std::shared_ptr<SceneCacheSlot> bounceSlot = nullptr);
    ~RenderEngine();
    RenderEngine(const RenderEngine&) = delete;
    RenderEngine& operator=(const RenderEngine&) = delete;

    void submit(const WorkItem& item);
    /// Queues several items at once (small ones of one frame may then render together).
    void submitAll(const std::vector<WorkItem>& items);
    /// A finished item, if any; waits up to waitSeconds for one.
    std::optional<TileResult> takeResult(double waitSeconds = 0.0);
    /// Items submitted and not yet taken back.
    int outstanding() const;
    /// Frame being rendered now, or -1.
    int currentFrame() const;
    /// The error that stopped the render thread, empty while all is well.
    std::string error() const;
    /// Drops queued items; the item in progress finishes.
    void cancelQueued();
    /// From now on items of v.epoch render as v says. Queued items of other epochs are
    /// dropped, and the one rendering stops between sub-tiles: none of them gives a result.
    void setView(const ViewSpec& v);
    /// The scene and timeline items render from once the item in progress is done (a viewer
    /// whose camera keys changed its timeline: the scene as loaded, with the new timeline).
    void setScene(Scene scene, anim::Timeline timeline);

    /// Renders item synchronously on the calling thread's pool (no queue): the pure function
    /// every mode reduces to. Public for tests. The 8-bit plane is RGBA when the scene's
    /// background is transparent.
    /// view: how an item of an interactive epoch renders (null: the job's own frame). cancel:
    /// renderRect's; the result is incomplete when it was set.
    /// bounceSlot: where the bounce cache is kept (null: a slot for this call alone).
    static TileResult render(Scene& scene, const anim::Timeline& tl, const RenderSettings& s, int threads,
                             const WorkItem& item, int& appliedFrame, bool linear = false, const ViewSpec* view = nullptr,
                             const std::atomic<bool>* cancel = nullptr,
                             const std::shared_ptr<SceneCacheSlot>& bounceSlot = nullptr);
    /// render() for items of one frame and epoch at once, their sub-tiles shared among the
    /// threads; each result is the one render() gives (busySeconds: its share of the wall time,
    /// by pixels).
    static std::vector<TileResult> renderTogether(Scene& scene, const anim::Timeline& tl, const RenderSettings& s,
                                                  int threads, const std::vector<WorkItem>& items, int& appliedFrame,
                                                  bool linear = false, const ViewSpec* view = nullptr,
                                                  const std::atomic<bool>* cancel = nullptr,
                                                  const std::shared_ptr<SceneCacheSlot>& bounceSlot = nullptr);

    /// The largest number of items rendered together so far (for tests).
    int largestBatch() const;
    int threads() const { return threads_; }

    /// A small item's sub-tiles (how many pieces its render is split into for the threads), and
    /// how many a batch of small items gathers a render thread: the master gives each rank
    /// enough small items to fill its threads (Master's credits).
    static int subTilesOf(const TileRect& rect, const RenderSettings& s);
    static constexpr int kSubTilesPerThread = 4;

private:
    void loop();
    /// The next items and how to render them: the queue's first, and the small items of the
    /// same frame and epoch behind it while together they have fewer sub-tiles than a few per
    /// thread; false when the engine stops.
    bool next(std::vector<WorkItem>& items, std::optional<ViewSpec>& view);

    Scene scene_;
    anim::Timeline timeline_;
    RenderSettings settings_;
    std::shared_ptr<SceneCacheSlot> bounceSlot_;  ///< the job's bounce cache, for all its frames
    int threads_;
    bool linear_;
    ItemRenderer itemRenderer_;
    int appliedFrame_ = -1;

    mutable std::mutex mutex_;
    std::condition_variable workCv_, resultCv_;
    std::deque<WorkItem> queue_;
    std::deque<TileResult> results_;
    int outstanding_ = 0;
    int current_ = -1;
    int largestBatch_ = 0;
    uint64_t currentEpoch_ = 0;
    std::optional<ViewSpec> view_;
    std::optional<std::pair<Scene, anim::Timeline>> nextScene_;
    std::atomic<bool> cancelCurrent_{false};
    bool stop_ = false;
    std::string error_;
    std::thread thread_;
};

}  // namespace rf::farm
