#include "farm/view/film_render.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "farm/output/output_lock.h"
#include "farm/output/png_sink.h"
#include "farm/cluster/run_farm.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::view {

farm::RenderJob filmJob(const FilmRequest& r, int ranks, std::string& note) {
    farm::RenderJob job;
    job.scenePath = r.scenePath;
    job.output = r.output;
    job.framesDir = r.framesDir;
    job.settings = r.settings;
    job.resume = r.resume;
    job.threads = r.threads;
    const anim::Timeline tl = anim::Timeline::fromScene(r.scene, r.timeline);
    job.timelineFrames = tl.frameCount();
    job.timelineFps = tl.fps();
    job.first = 0;
    job.last = job.timelineFrames - 1;
    job.mp4.fps = tl.fps();
    job.mp4.chunkFrames = farm::defaultChunkFrames(job.mp4.fps, job.timelineFrames);
    note = farm::checkMp4Options(job.settings.width, job.settings.height, job.mp4);
    const int renderers = ranks <= 2 ? ranks : ranks - 1;
    job.mode = farm::chooseMode(job.timelineFrames, renderers, job.settings.width, job.settings.height, job.modeWhy);
    // The manifest holds the digests of the files `render` would read for this scene path, so
    // that `rayfarm render … --resume` accepts (or refuses) the window's frames like its own.
    DiskFileSource fs;
    loadScene(r.scenePath, fs);
    const auto digests = farm::inputDigests(fs.bundle());
    if (job.resume && std::filesystem::exists(std::filesystem::path(job.framesDir) / "rayfarm-frames.json")) {
        farm::checkFramesManifest(job.framesDir, job.identity(), digests);
    } else {
        job.resume = false;
        farm::prepareFramesDir(job.framesDir);
        farm::writeFramesManifest(job.framesDir, job.identity(), digests);
    }
    return job;
}

FilmEnd renderFilm(farm::Transport& t, FilmRequest& r, const FilmCallbacks& cb, const std::atomic<bool>& cancel) {
    // One writer per output, as for `render`: a render of the same film elsewhere refuses, and
    // this one refuses while such a render runs (the window shows why).
    const OutputLock videoLock(r.output), framesLock(r.framesDir);
    std::string note;
    const farm::RenderJob job = filmJob(r, t.size(), note);
    if (!note.empty() && cb.log) cb.log("note: " + note);
    farm::FarmSinks sinks = farm::sinksForJob(job);

    farm::SharedScene shared;
    shared.scene = std::move(r.scene);
    shared.timeline = std::move(r.timeline);
    shared.bounceSlot = r.bounceSlot;
    farm::FarmOptions opts;
    opts.threads = job.threads;
    opts.cancel = &cancel;
    opts.quiet = true;
    opts.keepWorkers = true;  // they go back to the window's views
    opts.log = cb.log;
    opts.onFrame = [&](const farm::FarmProgress& p) {
        if (cb.onFrame) cb.onFrame(p.framesDone, p.framesTotal);
    };
    const farm::FarmOutcome o = farm::runFarm(t, job, shared, std::move(sinks), opts);
    FilmEnd end;
    end.framesInVideo = o.stats.frames;
    end.message = o.videoHolds;
    switch (o.end) {
    case farm::FarmEnd::Done: end.kind = FilmEnd::Done; break;
    case farm::FarmEnd::Cancelled:
    case farm::FarmEnd::Interrupted: end.kind = FilmEnd::Cancelled; break;
    case farm::FarmEnd::WorkerLost:
        end.kind = FilmEnd::RankLost;
        end.message = o.error + "; " + o.videoHolds;
        break;
    }
    return end;
}

}  // namespace rf::view
