#pragma once
/// What the window renders with: the farm's one entry point, runFarm, on a thread of its own
/// that owns the transport. Interactive frames are a view session (farm/cluster/view_session.h): each
/// request becomes a ViewOrder (one small 1 spp pass while moving; 1, 4, 16 … spp up to the
/// target at rest) whose every pass is an epoch that cancels older work on every rank. A film
/// (Ctrl+R) pauses the session, runs runFarm on the film's job with the same ranks, and the
/// session starts again after it. Alone, the transport is a one-rank loopback and rank 0
/// renders on its own threads; under mpirun, it is MPI and ranks 1…N−1 run runViewWorker.
#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "farm/view/camera_keys.h"
#include "farm/view/film_render.h"
#include "farm/cluster/run_farm.h"
#include "farm/cluster/transport.h"
#include "farm/view/view_frame.h"

namespace rf::farm {
class LoopbackHub;
}

namespace rf::view {

/// How the farm's session ended, for the window (any thread).
struct SessionEnd {
    std::string error;    ///< what stopped the rendering ("rank 2 stopped answering …")
    int lostRank = -1;    ///< the rank that died or fell silent, if that is why
    bool signalled = false;  ///< mpirun's SIGTERM (or Ctrl-C) ended it: SIGKILL follows soon
};

class FarmView {
public:
    /// t: rank 0's transport with ranks 1…N−1 in runViewWorker, or null to render alone on
    /// `threads` threads. scene: as loaded (the picture options applied); publish: where
    /// pictures go; onEnd: called once (on the farm's thread) if the session stops for good.
    /// bounceSlot: the bounce cache every session and film shares (null: one of the view's own).
    FarmView(farm::Transport* t, LoadedScene loaded, RenderSettings settings, int threads, Publish publish,
             std::function<void(const SessionEnd&)> onEnd, std::shared_ptr<SceneCacheSlot> bounceSlot = nullptr);
    /// Ends the session (and a film, its frames kept), then tells every rank to stop.
    ~FarmView();
    FarmView(const FarmView&) = delete;
    FarmView& operator=(const FarmView&) = delete;

    /// Replaces whatever is pending or rendering; returns the request's epoch (ViewFrame::epoch).
    uint64_t request(const ViewRequest& r);
    /// Plays another timeline from the next request on (timelineJson: {"timeline": …} as in
    /// TimelineSource::sections, serialised, or "" for none), over the scene as loaded.
    void setTimeline(const std::string& timelineJson);
    /// Renders the film through runFarm on this session's ranks; no views meanwhile.
    void startFilm(FilmRequest r, FilmCallbacks cb);
    /// Finished frames stay in the frames directory and in a playable MP4.
    void cancelFilm() { filmCancel_ = true; }
    bool filmCancelled() const { return filmCancel_; }
    /// What stopped the rendering; empty while all is well.
    std::string error() const;
    int threads() const { return threads_; }
    int ranks() const { return ranks_; }

    /// Moving frames render 1/scale of the target size (nextMovingScale).
    int movingScale() const { return scale_; }

private:
    void farmLoop();
    void runSession();
    void runFilm();
    void onPicture(const farm::FarmProgress& p);
    void sessionEnded(const farm::FarmOutcome& o);
    farm::ViewOrder orderFor(const ViewRequest& r, uint64_t id) const;
    void sendTimeline();
    void stopRanks();

    std::unique_ptr<farm::LoopbackHub> hub_;  ///< alone: a farm of one rank
    std::unique_ptr<farm::Transport> alone_;
    farm::Transport& t_;
    const Scene scene_;  ///< as loaded: every session and film starts from a copy
    const TimelineSource source_;  ///< the scene's timeline as loaded (its --animation stays)
    const RenderSettings settings_;
    const std::shared_ptr<SceneCacheSlot> bounceSlot_;  ///< built once, kept across sessions and films
    const int threads_, ranks_;
    Publish publish_;
    std::function<void(const SessionEnd&)> onEnd_;
    farm::ViewInbox inbox_;

    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::string timelineJson_;
    bool timelineChanged_ = false;
    std::optional<std::pair<FilmRequest, FilmCallbacks>> film_;
    std::optional<ViewRequest> current_;  ///< the request the pictures answer
    uint64_t currentId_ = 0, nextId_ = 0;
    bool currentAnswered_ = false;  ///< its last pass was published
    bool closing_ = false, ended_ = false;
    std::string error_;

    std::atomic<bool> sessionCancel_{false}, filmCancel_{false};
    std::atomic<int> scale_{1};  ///< movingScale_.scale(), for the window's thread
    MovingScale movingScale_;    ///< the farm's thread's
    std::vector<uint8_t> shown_;  ///< the last complete pass, under partial ones (farm thread)
    int shownW_ = 0, shownH_ = 0;
    std::thread thread_;
};

}  // namespace rf::view
