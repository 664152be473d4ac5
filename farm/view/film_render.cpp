#include "film_render.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "loopback_transport.h"
#include "messages.h"
#include "png_sink.h"
#include "run_farm.h"
#include "scene_loader.h"
#include "timeline.h"

namespace rf::view {

std::string encodeFilmStart(const std::string& workerJob, const std::string& timelineJson) {
    const uint64_t n = workerJob.size();
    std::string out(reinterpret_cast<const char*>(&n), sizeof n);
    return out + workerJob + timelineJson;
}

void decodeFilmStart(const std::string& bytes, std::string& workerJob, std::string& timelineJson) {
    uint64_t n = 0;
    if (bytes.size() < sizeof n) throw std::runtime_error("malformed film message");
    std::memcpy(&n, bytes.data(), sizeof n);
    if (n > bytes.size() - sizeof n) throw std::runtime_error("malformed film message");
    workerJob = bytes.substr(sizeof n, n);
    timelineJson = bytes.substr(sizeof n + n);
}

farm::RenderJob filmJob(const FilmRequest& r, int ranks, std::string& note) {
    farm::RenderJob job;
    job.scenePath = r.scenePath;
    job.output = r.output;
    job.framesDir = r.framesDir;
    job.settings = r.settings;
    job.resume = r.resume;
    job.threads = r.threads;
    const anim::Timeline tl = anim::Timeline::fromScene(r.scene);
    job.timelineFrames = tl.frameCount();
    job.timelineFps = tl.fps();
    job.first = 0;
    job.last = job.timelineFrames - 1;
    job.mp4.fps = tl.fps();
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

FilmRender::FilmRender(farm::Transport* t, FilmRequest r, FilmCallbacks cb) : t_(t), cb_(std::move(cb)) {
    thread_ = std::thread([this, req = std::move(r)]() mutable { run(std::move(req)); });
}

FilmRender::~FilmRender() {
    cancel_ = true;
    if (thread_.joinable()) thread_.join();
}

void FilmRender::run(FilmRequest r) {
    FilmEnd end;
    try {
        if (t_) {
            end = render(*t_, r);
        } else {
            farm::LoopbackHub hub(1);  // alone: a farm of one rank, rendering on its own threads
            farm::LoopbackTransport alone(hub, 0);
            end = render(alone, r);
        }
    } catch (const std::exception& e) {
        end.kind = FilmEnd::Failed;
        end.message = e.what();
    }
    if (cb_.onEnd) cb_.onEnd(end);
}

FilmEnd FilmRender::render(farm::Transport& t, FilmRequest& r) {
    std::string note;
    const farm::RenderJob job = filmJob(r, t.size(), note);
    if (!note.empty() && cb_.log) cb_.log("note: " + note);
    farm::FarmSinks sinks = farm::sinksForJob(job);
    // Every other rank leaves its view loop for runFarm's work items; messages from rank 0
    // arrive in order, so no work item overtakes this.
    const std::string start = encodeFilmStart(farm::encodeWorkerJob(job), r.timelineJson);
    for (int rank = 1; rank < t.size(); ++rank) t.send(rank, farm::kTagFilm, start);

    farm::SharedScene shared;
    shared.scene = std::move(r.scene);
    farm::FarmOptions opts;
    opts.threads = job.threads;
    opts.cancel = &cancel_;
    opts.quiet = true;
    opts.log = cb_.log;
    opts.onFrame = [&](const farm::FarmProgress& p) {
        if (cb_.onFrame) cb_.onFrame(p.framesDone, p.framesTotal);
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
