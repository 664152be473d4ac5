#pragma once
/// The window's Render action: the film to an MP4 through the farm's one entry point, runFarm,
/// on the ranks the window already has (FarmView runs it on the thread that owns the
/// transport, between two view sessions). Under mpirun the other ranks' render engines serve
/// it as they serve the window's views; alone, rank 0 is the only rank of a one-rank transport.
/// Progress and the end come back through callbacks on that thread: the window posts them to
/// its own.
#include <atomic>
#include <functional>
#include <string>

#include "farm/cluster/render_job.h"
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"
#include "engine/util/settings.h"
#include "farm/cluster/transport.h"

namespace rf::view {

struct FilmRequest {
    /// The scene file render would read (the saved scene when there are keys): it names the
    /// frames directory's manifest and the digests that a later --resume compares.
    std::string scenePath;
    Scene scene;               ///< what the window renders
    TimelineSource timeline;   ///< with this timeline
    std::string timelineJson;  ///< that timeline's sections ({"timeline": …} or ""), for the other ranks
    RenderSettings settings;
    std::string output, framesDir;
    bool resume = false;  ///< keep the frames a cancelled run left in framesDir
    int threads = 1;      ///< rank 0's render threads
    /// The window's bounce cache, which the film's frames use as the views' did (null: its own).
    std::shared_ptr<SceneCacheSlot> bounceSlot;
};

struct FilmEnd {
    enum Kind { Done, Cancelled, Failed, RankLost } kind = Failed;
    std::string message;  ///< what failed, or which rank was lost
    int framesInVideo = 0;
};

struct FilmCallbacks {
    std::function<void(int done, int total)> onFrame;  ///< after each frame reaches the MP4
    std::function<void(const std::string&)> log;        ///< runFarm's lines ("resume: …")
    std::function<void(const FilmEnd&)> onEnd;          ///< once, after runFarm returned
};

/// The job runFarm renders, as `rayfarm render r.scenePath -o r.output --frames-dir
/// r.framesDir` with the window's picture settings would decide it. Prepares the frames
/// directory (fresh, or checked for a resume); throws UsageError on a mismatch.
farm::RenderJob filmJob(const FilmRequest& r, int ranks, std::string& note);

/// Renders r's film through runFarm on t, whose ranks 1…N−1 serve it from their view loop
/// (runViewWorker) with the timeline the window last sent them; they stay in that loop after
/// it. cancel: like Ctrl-C for render (the MP4 holds the frames done, their PNGs are kept).
/// Runs on the thread that owns t; the callbacks run there too.
FilmEnd renderFilm(farm::Transport& t, FilmRequest& r, const FilmCallbacks& cb, const std::atomic<bool>& cancel);

}  // namespace rf::view
