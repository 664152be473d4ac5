#include "farm/cluster/run_farm.h"

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <utility>

#include <sys/resource.h>

#include "engine/scene/background.h"
#include "farm/cluster/bench_free_work.h"
#include "farm/cluster/chunk_collector.h"
#include "farm/cluster/chunk_workshop.h"
#include "farm/output/contact_sheet.h"
#include "engine/util/errors.h"
#include "farm/output/exr_frames.h"
#include "farm/cluster/frame_assembler.h"
#include "farm/output/gif_sink.h"
#include "engine/util/image.h"
#include "farm/process/interrupt.h"
#include "farm/cluster/master.h"
#include "farm/output/mp4_sink.h"
#include "farm/output/png_sink.h"
#include "engine/integrators/render.h"
#include "farm/cluster/render_engine.h"
#include "farm/process/signal_deadline.h"
#include "anim/timeline.h"
#include "farm/cluster/worker.h"

namespace rf::farm {

using Clock = std::chrono::steady_clock;

namespace {

double secondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

/// A kept frame's file, whole (it was checked against its digest when the run started).
std::string readFileBytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (!f.good() && !f.eof()) throw std::runtime_error(path + ": cannot read the kept frame");
    return bytes;
}

/// The frames of the output, and which of them an earlier run left in the frames directory.
struct FramePlan {
    anim::FrameRanges order;     ///< every frame of the output
    anim::FrameRanges kept;      ///< read back from disk (--resume)
    anim::FrameRanges toRender;  ///< the rest
};

FramePlan planFrames(const RenderJob& job, const std::function<void(const std::string&)>& log) {
    FramePlan p;
    p.order = job.frames();
    if (job.resume) {
        std::vector<int> corrupt;
        p.kept = keptFramesForJob(job, &corrupt);
        for (const std::string& note : damagedFrameNotes(job.framesDir, corrupt, p.order, job.exrFrames)) log("note: " + note);
        log("resume: " + std::to_string(p.kept.count()) + " of " + std::to_string(p.order.count()) + " frames kept in " +
            job.framesDir + ", " + std::to_string(p.order.count() - p.kept.count()) + " to render");
    }
    p.toRender = p.order.minus(p.kept);
    return p;
}

/// Pixel mode's tile size: big tiles mean fewer messages; small frames still get enough tiles
/// to keep every rank's hands full.
int pixelTile(const RenderJob& job, int renderers, int credits) {
    const int width = job.settings.width, height = job.settings.height;
    int tile = job.tileSize;
    while (tile > 16 && int(makeTiles(width, height, tile).size()) < 2 * renderers * credits) tile /= 2;
    return tile;
}

/// Pixel or frame scheduler, sized so every renderer's credits can be filled.
std::unique_ptr<Scheduler> makeScheduler(const RenderJob& job, anim::FrameRanges toRender, int renderers, int credits) {
    const int width = job.settings.width, height = job.settings.height;
    if (job.mode != Mode::Pixel) return makeFrameScheduler(std::move(toRender), width, height, renderers * credits + 2);
    const int tile = pixelTile(job, renderers, credits);
    const int tilesPerFrame = int(makeTiles(width, height, tile).size());
    const int window = 2 + (renderers * credits + tilesPerFrame - 1) / tilesPerFrame;
    return makePixelScheduler(std::move(toRender), width, height, tile, window);
}

/// The sinks, each on its own thread.
struct AsyncSinks {
    std::unique_ptr<AsyncSink> video, pictures, frames;
    /// Run between closing the PNG frames and the video (frame mode with chunked encoding: the
    /// frames after the last whole chunk, from their PNGs).
    std::function<void()> beforeVideoCloses;

    explicit AsyncSinks(FarmSinks s) {
        if (!s.video) throw std::invalid_argument("runFarm: a video sink is required");
        video = std::make_unique<AsyncSink>(std::move(s.video), 4);
        if (s.pictures) pictures = std::make_unique<AsyncSink>(std::move(s.pictures), 4);
        if (s.frames) frames = std::make_unique<AsyncSink>(std::move(s.frames), 4);
    }
    /// Closes every sink (the PNG frames first: they are what a resume needs); rethrows the first error.
    void close() {
        std::exception_ptr first;
        auto closing = [&](const std::function<void()>& f) {
            try {
                f();
            } catch (...) {
                if (!first) first = std::current_exception();
            }
        };
        if (frames) closing([&] { frames->close(); });
        if (beforeVideoCloses) closing(std::exchange(beforeVideoCloses, nullptr));
        if (pictures) closing([&] { pictures->close(); });
        closing([&] { video->close(); });
        if (first) std::rethrow_exception(first);
    }
};

/// One run on rank 0: the parts runFarm wires together, and the steps after the master's loop.
class FarmRun {
public:
    FarmRun(Transport& t, const RenderJob& job, const FarmOptions& opts, FarmSinks sinks)
        : t_(t), job_(job), opts_(opts), sinks_(std::move(sinks)) {}
    ~FarmRun() {
        if (closer_.joinable()) closer_.join();
    }

    FarmOutcome run(SharedScene& shared);

private:
    MasterConfig masterConfig(int totalFrames) const;
    void emit(ReadyFrame& rf, int total);
    ChunkOrder orderFor(const WorkItem& item) const;
    void onChunkFrame(const ChunkFrame& f);
    void emitChunk(int chunk, std::string& bytes, int total);
    void videoFromKeptFrames();
    MasterOutcome runMaster(Master& master, SignalDeadline& deadline);
    int lastWords();
    std::string videoHolds() const;
    std::string closeSinks(Master& master, const MasterOutcome& o);
    void startClose();
    bool closeFinishedWithin(double seconds) const;
    void finishClose();
    FarmOutcome conclude(Master& master, const MasterOutcome& o, const std::string& silent, const SharedScene& shared);
    RunStats stats(const MasterOutcome& o, Clock::time_point end, const SharedScene& shared) const;

    Transport& t_;
    const RenderJob& job_;
    const FarmOptions& opts_;
    AsyncSinks sinks_;
    bool rank0Renders_ = false;
    std::atomic<int> framesPassed_{0};
    int encodedKept_ = 0;
    /// Chunked encoding on the rendering ranks: each chunk encoded by one rank, which renders its
    /// frames (frame mode; the film's last frames come from every rank) or assembles it from
    /// every rank's tiles (pixel mode).
    bool chunked_ = false;
    ChunkPlan plan_;
    anim::FrameRanges kept_;
    std::unique_ptr<ChunkCollector> collector_;
    double rankEncodeSeconds_ = 0.0;  ///< chunk encoders' time on the ranks that encoded them
    int chunksJoined_ = 0;
    int silentRank_ = -1;
    std::set<int> framesHeard_;  ///< chunked encoding: frames whose ChunkFrame came
    Clock::time_point end_{};
    /// After an interrupt the sinks close on a thread of their own (startClose), so the
    /// interrupted line goes out before mpirun's SIGKILL even while a slow encoder drains.
    std::thread closer_;
    std::atomic<bool> closed_{false};
    std::exception_ptr closeError_;
};

/// How long an interrupted run waits for its video to close before saying what it holds:
/// mpirun sends SIGKILL about a second after SIGTERM, and the file plays at every moment
/// (mp4_sink.h), so the line must not wait for a slow encoder.
constexpr double kInterruptCloseBudget = 0.6;

MasterConfig FarmRun::masterConfig(int totalFrames) const {
    MasterConfig cfg;
    cfg.workerTimeout = job_.workerTimeout;
    // Pixel mode: a 64x64 tile renders in a millisecond or less (an empty one in a tenth), and
    // a round trip to rank 0 takes up to a few (both ends look every 2 ms), so each rank holds
    // eight to never wait for the next. 2CylinderEngine, 2 ranks: 4 credits 33.7 fps, 8 34.8,
    // 16 34.1 (1 ms looks); 8 with 2 ms looks 36.4.
    cfg.credits = job_.mode == Mode::Pixel ? 8 : 2;
    cfg.liveProgress = opts_.liveProgress;
    cfg.quiet = opts_.quiet;
    cfg.progressLabel = opts_.progressLabel;
    cfg.totalFrames = totalFrames;
    cfg.cancel = opts_.cancel;
    // Its own epoch: on workers that served an earlier run (a viewer's cancelled film), late
    // results of that run are dropped rather than taken for work this one never gave.
    cfg.epoch = newEpoch();
    // A lost worker's work goes to the others (when the launcher keeps the job alive). Not in a
    // viewer's film (keepWorkers): its ranks go back to the window's views, which stop at a lost
    // rank (view_session.h), so the film stops there too, as the window reports.
    cfg.requeueLost = !opts_.keepWorkers;
    cfg.maxFrameFailures = job_.maxFrameFailures;
    cfg.log = opts_.log;
    return cfg;
}

void FarmRun::emit(ReadyFrame& rf, int total) {
    const int width = job_.settings.width, height = job_.settings.height;
    if (rf.onDisk) {
        int w = 0, h = 0;
        rf.rgb = readImage8(framePngPath(job_.framesDir, rf.frame), w, h, job_.layout().channels);
        if (w != width || h != height) throw std::runtime_error(framePngPath(job_.framesDir, rf.frame) + ": wrong size");
        ++encodedKept_;
    }
    sinks_.video->write(rf.frame, rf.rgb);
    if (sinks_.pictures && sinks_.pictures->wants(rf.frame)) sinks_.pictures->write(rf.frame, rf.rgb);
    ++framesPassed_;
    if (opts_.onFrame) opts_.onFrame(FarmProgress{rf.frame, framesPassed_, total, rf.onDisk, &rf.rgb});
}

/// A chunk as it goes out to the rank that encodes it: the PNGs of its frames kept by an
/// earlier run (read here, decoded by that rank; only the other frames are handed out), the
/// frames the pictures want, and whether to send PNGs back.
ChunkOrder FarmRun::orderFor(const WorkItem& item) const {
    ChunkOrder o;
    o.item = item;
    o.sendPngs = sinks_.frames ? 1 : 0;
    for (int f = item.frame; f < item.frame + item.frames; ++f) {
        if (kept_.contains(f)) o.kept.emplace_back(f, readFileBytes(framePngPath(job_.framesDir, f)));
        if (sinks_.pictures && sinks_.pictures->wants(f)) o.rawWanted.push_back(f);
    }
    return o;
}

void FarmRun::onChunkFrame(const ChunkFrame& f) {
    // A chunk opened again after its rank was lost sends its frames again: the same pixels.
    if (!framesHeard_.insert(f.frame).second) return;
    if (!f.png.empty() && sinks_.frames) sinks_.frames->writePng(f.frame, f.png, f.pngSha256);
    if (!f.pixels.empty()) collector_->holdPixels(f.frame, f.pixels);
    if (f.wasKept) ++encodedKept_;
}

void FarmRun::emitChunk(int chunk, std::string& bytes, int total) {
    EncodedChunk c = parseChunk(bytes);
    if (c.index != chunk || c.frames != plan_.framesIn(chunk))
        throw std::runtime_error("chunk " + std::to_string(chunk) + " arrived holding chunk " + std::to_string(c.index) + " of " +
                                 std::to_string(c.frames) + " frames");
    rankEncodeSeconds_ += c.encodeSeconds;
    sinks_.video->writeChunk(c);
    ++chunksJoined_;
    for (auto& [frame, px] : collector_->takePixels(chunk)) sinks_.pictures->write(frame, px);
    for (int f = plan_.firstFrame(chunk); f <= plan_.lastFrame(chunk); ++f) {
        ++framesPassed_;
        if (opts_.onFrame) opts_.onFrame(FarmProgress{f, framesPassed_, total, kept_.contains(f), nullptr});
    }
}

/// Chunked encoding on the ranks, when the run stops early (a signal, a lost worker): the video
/// holds the whole chunks joined so far; the frames after them whose PNGs reached rank 0 go in
/// too, encoded here into a chunk of their own, so that the video holds every frame finished in
/// order, as when rank 0 encodes. (A resume rewrites the video whole.)
void FarmRun::videoFromKeptFrames() {
    if (!chunked_ || job_.framesDir.empty()) return;
    const int width = job_.settings.width, height = job_.settings.height;
    for (int f = job_.first + framesPassed_; f <= job_.last; ++f) {
        const std::string path = framePngPath(job_.framesDir, f);
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) return;
        int w = 0, h = 0;
        std::vector<uint8_t> rgb = readImage8(path, w, h, job_.layout().channels);
        if (w != width || h != height) return;
        sinks_.video->write(f, rgb);
        if (sinks_.pictures && sinks_.pictures->wants(f)) sinks_.pictures->write(f, rgb);
        ++framesPassed_;
    }
}

/// Turns the outcome into a failure with `what`, unless it already is one (the first error is
/// the one the user reads).
void failWith(MasterOutcome& o, const std::string& what) {
    if (o.end == RunEnd::Failed) return;
    o.end = RunEnd::Failed;
    o.message = what;
}

/// The master's loop. Its end is claimed from the deadline's watchdog, which otherwise winds the
/// run down by itself (lastWords) when a signal finds this thread held inside MPI. An error
/// thrown from the loop (a sink that cannot write, on the master's thread) is a Failed outcome,
/// as one caught inside it is: conclude words every failure the same way.
MasterOutcome FarmRun::runMaster(Master& master, SignalDeadline& deadline) {
    MasterOutcome o;
    try {
        o = master.run();
    } catch (const std::exception& e) {
        failWith(o, e.what());
    } catch (...) {
        if (!deadline.claim()) deadline.waitForEnd();
        master.stopWorkers();
        throw;
    }
    if (!deadline.claim()) deadline.waitForEnd();
    return o;
}

/// On the watchdog's thread, the main one being held inside MPI: the video is closed with the
/// frames done so far, and onEnd hears of the interrupt. Returns the exit status.
int FarmRun::lastWords() {
    startClose();
    // The watchdog fires 0.25 s after the signal: less time is left than on the main thread.
    closeFinishedWithin(kInterruptCloseBudget - 0.25);
    FarmOutcome out;
    out.videoHolds = videoHolds();
    out.signal = interruptSignal();
    out.end = FarmEnd::Interrupted;
    if (opts_.onEnd) opts_.onEnd(out);
    try {
        finishClose();
    } catch (...) {
        // The video is as complete as it gets, and the user has heard how the run ended.
    }
    if (opts_.onLastWords) opts_.onLastWords();
    return signalExitStatus(out.signal ? out.signal : SIGTERM);
}

void FarmRun::startClose() {
    closer_ = std::thread([this] {
        try {
            sinks_.close();
        } catch (...) {
            closeError_ = std::current_exception();
        }
        closed_ = true;
    });
}

/// True once the sinks closed; waits at most `seconds` for it.
bool FarmRun::closeFinishedWithin(double seconds) const {
    const auto until = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
    while (!closed_ && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return closed_;
}

/// Waits for startClose's thread; rethrows what the closing threw.
void FarmRun::finishClose() {
    if (closer_.joinable()) closer_.join();
    if (std::exception_ptr e = std::exchange(closeError_, nullptr)) std::rethrow_exception(e);
}

/// What the video file holds now: the frames flushed to it (they play if the process dies next),
/// or for a sink that writes only at close, the frames it took. While an interrupted run's
/// encoder still drains (startClose), also what it will hold when that is done.
std::string FarmRun::videoHolds() const {
    int encoded = sinks_.video->framesInOutput();
    if (encoded < 0) encoded = sinks_.video->framesDone();
    std::string s = "the video " + printable(job_.output) + " holds " +
                    (encoded ? (encoded == 1 ? "frame " : "frames ") + frameSpan(job_.first, job_.first + encoded - 1)
                             : std::string("no frames")) + " of " +
                    frameSpan(job_.first, job_.last);
    if (closer_.joinable() && !closed_ && framesPassed_ > encoded)
        s += " so far, " + frameSpan(job_.first, job_.first + framesPassed_ - 1) + " once its encoder finishes";
    return s;
}

/// Closes the sinks. After an interrupt, under mpirun SIGKILL follows SIGTERM within about a
/// second: the video closes on its own thread while the master finds out whether a worker's
/// death is why we were signalled; returns that worker's description, or "". A close that takes
/// longer than kInterruptCloseBudget goes on after the outcome is told (conclude).
std::string FarmRun::closeSinks(Master& master, const MasterOutcome& o) {
    if (o.end != RunEnd::Interrupted) {
        // A film that ended (done, or failed for good) needs nothing more of the workers: they
        // hear so before the close (an MP4's remux takes seconds on a long film), since a worker
        // leaves when rank 0 is silent for --timeout, and under a plain mpirun its exit would
        // end the job mid-remux. A lost worker's end keeps its own stop message.
        if (o.end != RunEnd::WorkerLost && !opts_.keepWorkers) master.stopWorkers();
        sinks_.close();
        return "";
    }
    const auto start = Clock::now();
    startClose();
    // A cancel is the caller's wish: no worker died for it.
    std::string silent;
    if (t_.size() > 1 && interruptSignal()) silent = master.findSilentWorker(0.5, &silentRank_);
    if (closeFinishedWithin(kInterruptCloseBudget - secondsBetween(start, Clock::now()))) finishClose();
    return silent;
}

FarmOutcome FarmRun::run(SharedScene& shared) {
    StopWorkersOnThrow setUp(t_);
    if (opts_.keepWorkers) setUp.dismiss();  // a viewer's film: its workers serve the next views
    const int ranks = t_.size();
    rank0Renders_ = ranks <= 2;  // with more ranks, rank 0's core serves the master and encoder
    const int renderers = rank0Renders_ ? ranks : ranks - 1;
    const FramePlan plan = planFrames(job_, opts_.log);
    MasterConfig cfg = masterConfig(int(plan.order.count()));
    chunked_ = job_.chunkedFrames;
    plan_ = ChunkPlan{job_.first, job_.last, std::max(kMinChunkFrames, job_.mp4.chunkFrames)};
    kept_ = plan.kept;
    cfg.keptFrames = int(plan.kept.count());
    const int width = job_.settings.width, height = job_.settings.height;
    cfg.framePixels = int64_t(width) * height;
    if (job_.mode == Mode::Pixel) {
        // A rank with many threads holds more small tiles, so that rendered together they fill
        // its threads (RenderEngine).
        const int tile = pixelTile(job_, renderers, cfg.credits);
        cfg.subTilesPerItem = RenderEngine::subTilesOf(TileRect{0, 0, tile, tile}, job_.settings);
    }
    std::unique_ptr<Scheduler> sched;
    if (!chunked_)
        sched = makeScheduler(job_, plan.toRender, renderers, cfg.credits);
    else if (job_.mode == Mode::Frame)  // a chunk open per renderer, two more while their last frames finish
        sched = makeChunkFrameScheduler(plan_, plan.kept, width, height, renderers + 2);
    else  // a chunk open per renderer and one more: as many encoders at work as ranks
        sched = makeChunkTileScheduler(plan_, plan.kept, width, height, pixelTile(job_, renderers, cfg.credits), renderers + 1);
    FrameAssembler assembler(job_.settings.width, job_.settings.height, plan.order, plan.kept, job_.layout());
    anim::Timeline timeline = anim::Timeline::fromScene(shared, job_.fpsOption);
    std::unique_ptr<RenderEngine> local;
    if (rank0Renders_)
        local = std::make_unique<RenderEngine>(std::move(shared.scene), timeline, job_.settings, opts_.threads, job_.exrFrames,
                                               benchFreeWorkRenderer(job_.exrFrames), shared.bounceSlot);
    std::unique_ptr<ChunkWorkshop> localShop;
    if (chunked_ && local) localShop = std::make_unique<ChunkWorkshop>(*local, chunkVideoSpec(job_), 0);

    const int total = int(plan.order.count());
    Master master(t_, *sched, assembler, local.get(), [&](ReadyFrame& rf) { emit(rf, total); }, cfg);
    if (sinks_.frames)
        master.onFrameComplete([&](int frame, const std::vector<uint8_t>& rgb) { sinks_.frames->write(frame, rgb); });
    if (chunked_) {
        collector_ = std::make_unique<ChunkCollector>(plan_);
        Master::ChunkHooks hooks;
        hooks.collector = collector_.get();
        hooks.local = localShop.get();
        hooks.orderFor = [this](const WorkItem& item) { return orderFor(item); };
        hooks.onFrame = [this](const ChunkFrame& f) { onChunkFrame(f); };
        hooks.emitChunk = [this, total](int chunk, std::string& bytes) { emitChunk(chunk, bytes, total); };
        master.useChunks(std::move(hooks));
        sinks_.beforeVideoCloses = [this] { videoFromKeptFrames(); };
    }
    // mpirun's SIGKILL follows its SIGTERM within about a second (signal_deadline.h).
    SignalDeadline deadline(0.25, [this] { return lastWords(); });
    setUp.dismiss();
    MasterOutcome o = runMaster(master, deadline);
    std::string silent;
    try {
        silent = closeSinks(master, o);
    } catch (const std::exception& e) {
        failWith(o, e.what());  // a frame write that failed last surfaces here, at the close
    }
    end_ = Clock::now();
    // Rank 0's engine finishes the item in hand before it goes (in frame mode a whole frame,
    // seconds at a high spp): only once the user has been told how the run ended.
    FarmOutcome out = conclude(master, o, silent, shared);
    localShop.reset();
    local.reset();
    return out;
}

FarmOutcome FarmRun::conclude(Master& master, const MasterOutcome& o, const std::string& silent, const SharedScene& shared) {
    FarmOutcome out;
    out.videoHolds = videoHolds();
    out.stats = stats(o, end_, shared);
    out.lostWorkers = int(o.lost.size());
    if (o.end == RunEnd::WorkerLost || !silent.empty()) {
        // The lost worker cannot be told to stop, and mpirun waits for it: the caller aborts.
        out.end = FarmEnd::WorkerLost;
        out.error = silent.empty() ? o.message : silent;
        out.lostRank = silent.empty() ? o.lostRank : silentRank_;
        out.abortRanks = t_.size() > 1;
        if (opts_.onEnd) opts_.onEnd(out);
        return out;
    }
    if (o.end == RunEnd::Interrupted) {
        out.signal = interruptSignal();
        out.end = out.signal ? FarmEnd::Interrupted : FarmEnd::Cancelled;
        if (opts_.onEnd) opts_.onEnd(out);  // before the workers hear: SIGKILL is near
        if (!opts_.keepWorkers) master.stopWorkers();
        try {
            finishClose();  // a slow encoder still draining: the file plays what it holds meanwhile
        } catch (const std::exception& e) {
            opts_.log(std::string("error: ") + e.what());
        }
        out.videoHolds = videoHolds();
        return out;
    }
    if (!opts_.keepWorkers) master.stopWorkers();
    // Every failure, wherever it was caught (inside the master's loop, thrown from it, or at the
    // close), in one form: what failed, then what the video holds.
    if (o.end == RunEnd::Failed) throw std::runtime_error(o.message + "; " + out.videoHolds);
    if (!job_.statsPath.empty()) writeStatsJson(job_.statsPath, out.stats);
    if (opts_.onEnd) opts_.onEnd(out);
    return out;
}

RunStats FarmRun::stats(const MasterOutcome& o, Clock::time_point end, const SharedScene& shared) const {
    RunStats s;
    s.frames = sinks_.video->framesDone();
    const auto firstDispatch = o.firstDispatch == Clock::time_point{} ? opts_.wallStart : o.firstDispatch;
    s.renderSeconds = secondsBetween(firstDispatch, std::max(sinks_.video->lastDone(), o.firstDispatch));
    s.sustainedFps = s.renderSeconds > 0.0 ? s.frames / s.renderSeconds : 0.0;
    s.wallSeconds = secondsBetween(opts_.wallStart, end);
    // Chunks encoded on the ranks are encoder time too; rank 0's video
    // thread then only joins them (mux_s).
    s.encodeSeconds = sinks_.video->busySeconds() + rankEncodeSeconds_;
    s.width = job_.settings.width;
    s.height = job_.settings.height;
    s.mode = job_.mode == Mode::Pixel ? "pixel" : "frame";
    s.ranks = t_.size();
    s.threadsPerRank = opts_.threads;
    s.rays = o.rays;
    s.perRank = o.perRank;
    for (const LostWorker& l : o.lost) s.lostWorkers.push_back({l.rank, l.host, l.atSeconds, l.doing, l.requeued});
    s.extra["frames_rendered"] = double(s.frames - encodedKept_);
    s.extra["frames_kept"] = double(encodedKept_);
    s.extra["video_fps"] = job_.mp4.fps;
    s.extra["exposure_ev"] = job_.settings.exposure;  // as given, or as metered by --exposure auto
    s.extra["encoder_share"] = s.renderSeconds > 0 ? s.encodeSeconds / s.renderSeconds : 0.0;
    s.extra["png_s"] = sinks_.frames ? sinks_.frames->busySeconds() : 0.0;
    s.extra["load_s"] = shared.loadSeconds;
    s.extra["chunk_frames"] = job_.mp4.chunkFrames;
    s.extra["mux_s"] = sinks_.video->busySeconds();
    s.extra["rank_encode_s"] = rankEncodeSeconds_;
    s.extra["chunks_from_ranks"] = chunksJoined_;
    struct rusage ru {};
    if (getrusage(RUSAGE_SELF, &ru) == 0)  // rank 0's whole process: what bounds the farm
        s.extra["rank0_cpu_s"] = double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
    s.extra["scene_bytes"] = double(shared.bundleBytes);
    s.extraText["mode_reason"] = job_.modeWhy;
    s.extraText["rank0_renders"] = rank0Renders_ ? "yes" : "no";
    s.extraText["chunks_encoded_by"] = !chunked_ ? "rank 0" : job_.mode == Mode::Frame ? "the rendering ranks" : "the assembling ranks";
    s.extraText["encoder"] = videoFormatOf(job_.output, job_.mp4).describe;
    return s;
}

}  // namespace

std::string frameSpan(int first, int last) {
    return first == last ? std::to_string(first) : std::to_string(first) + "–" + std::to_string(last);
}

namespace {

/// One sink, or a TeeSink over several.
std::unique_ptr<FrameSink> teeOf(std::vector<std::unique_ptr<FrameSink>> sinks) {
    return sinks.size() == 1 ? std::move(sinks[0]) : std::make_unique<TeeSink>(std::move(sinks));
}

}  // namespace

FarmSinks sinksForJob(const RenderJob& job, std::function<double(int)> frameTime) {
    const int w = job.settings.width, h = job.settings.height;
    const PixelLayout layout = job.layout();
    FarmSinks s;
    const VideoFormat video = videoFormatOf(job.output, job.mp4);
    if (video.container == Container::Gif) {
        const std::string dither = video.encoderOptions.at(0).second;
        s.video = std::make_unique<GifSink>(job.output, w, h, layout.channels, job.mp4.fps, dither);
    } else {
        // A resume keeps the earlier video until the new one catches up.
        s.video = std::make_unique<Mp4Sink>(job.output, w, h, job.mp4, job.resume ? job.last - job.first + 1 : 0);
    }
    if (!frameTime) frameTime = [fps = job.mp4.fps](int f) { return f / fps; };
    std::vector<std::unique_ptr<FrameSink>> pictures;
    if (!job.contactSheet.empty())
        pictures.push_back(std::make_unique<ContactSheetSink>(job.contactSheet, w, h, layout.channels, job.first, job.last, frameTime));
    if (!job.poster.empty())
        pictures.push_back(std::make_unique<PosterSink>(job.poster, job.posterFrame >= 0 ? job.posterFrame : job.first, w, h, layout.channels));
    if (!pictures.empty()) s.pictures = teeOf(std::move(pictures));
    if (!job.framesDir.empty()) {
        std::vector<std::unique_ptr<FrameSink>> frames;
        frames.push_back(std::make_unique<PngSink>(job.framesDir, w, h, layout.channels));
        if (job.exrFrames) frames.push_back(std::make_unique<ExrSink>(job.framesDir, w, h, layout));
        s.frames = teeOf(std::move(frames));
    }
    return s;
}

anim::FrameRanges keptFramesForJob(const RenderJob& job, std::vector<int>* corrupt) {
    const anim::FrameRanges order = job.frames();
    const int w = job.settings.width, h = job.settings.height;
    const anim::FrameRanges kept = findKeptFrames(job.framesDir, order, w, h, corrupt, job.layout().channels);
    if (!job.exrFrames) return kept;
    return kept.intersect(findKeptExrFrames(job.framesDir, order, w, h));
}

FarmOutcome runFarm(Transport& t, const RenderJob& job, SharedScene& shared, FarmSinks sinks, const FarmOptions& opts) {
    if (opts.views) return runViewSession(t, job, shared, opts);
    FarmOptions o = opts;
    if (!o.log) o.log = [](const std::string& line) { writeStderrText("rayfarm: " + line + "\n"); };
    FarmRun run(t, job, o, std::move(sinks));
    return run.run(shared);
}

int runFarmWorker(Transport& t, SharedScene& shared, double fpsOption, int threads, double masterTimeout,
                  double firstWordTimeout) {
    try {
        WorkerOutputs outputs;
        std::string chunkVideo;
        const RenderSettings settings = decodeWorkerJob(shared.job, &outputs, &chunkVideo);
        // The background as rank 0 decided it: the broadcast carries the scene's files, not rank 0's scene.
        applyBackground(outputs.background, shared.scene);
        // Every rank parsed the same options, so the worker's timeline matches rank 0's.
        anim::Timeline timeline = anim::Timeline::fromScene(shared, fpsOption);
        RenderEngine engine(std::move(shared.scene), timeline, settings, threads, outputs.linear != 0,
                            benchFreeWorkRenderer(outputs.linear != 0), shared.bounceSlot);
        if (chunkVideo.empty()) return runWorker(t, engine, masterTimeout, nullptr, nullptr, firstWordTimeout);
        // This rank encodes chunks itself, as rank 0 would: chunks whose frames it renders (frame
        // mode, with the film's last frames from other ranks too), or assembles from every
        // rank's tiles (pixel mode).
        ChunkWorkshop shop(engine, decodeChunkVideoSpec(chunkVideo), t.rank());
        return runWorker(t, engine, masterTimeout, nullptr, &shop, firstWordTimeout);
    } catch (const std::exception& e) {
        reportWorkerError(t, e.what());
        return 1;
    }
}

}  // namespace rf::farm
