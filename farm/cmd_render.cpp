// rayfarm render: the timeline to an MP4, as one process or as an MPI farm. This file wires the
// parts together; scheduling, messages, sinks and the loops live in their own files.
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sched.h>
#include <thread>

#include "cli.h"
#include "exposure_meter.h"
#include "errors.h"
#include "frame_assembler.h"
#include "image.h"
#include "interrupt.h"
#include "master.h"
#include "mp4_sink.h"
#include "output_check.h"
#include "png_sink.h"
#include "preview_spawn.h"
#include "progress.h"
#include "render.h"
#include "render_engine.h"
#include "render_job.h"
#include "run_stats.h"
#include "scene_broadcast.h"
#include "timeline.h"
#include "transport.h"
#include "worker.h"

namespace rf::cli {

using namespace rf::farm;
using Clock = std::chrono::steady_clock;

namespace {

double secondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

std::string shellQuote(const std::string& s) {
    if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./:=,+@%") == std::string::npos)
        return s;
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// How this executable was invoked (argv[0]), for the resume hint.
std::string invokedAs() {
    std::ifstream f("/proc/self/cmdline", std::ios::binary);
    std::string arg0;
    std::getline(f, arg0, '\0');
    return arg0.empty() ? "rayfarm" : arg0;
}

std::string resumeCommand(const std::vector<std::string>& args, int ranks) {
    std::string cmd = (ranks > 1 ? "mpirun -np " + std::to_string(ranks) + " " : std::string()) + shellQuote(invokedAs()) + " render";
    bool hasResume = false;
    for (const std::string& a : args) {
        cmd += " " + shellQuote(a);
        hasResume = hasResume || a == "--resume";
    }
    return hasResume ? cmd : cmd + " --resume";
}

std::string frameSpan(int first, int last) {
    return first == last ? std::to_string(first) : std::to_string(first) + "–" + std::to_string(last);
}

/// CPUs this process may run on: mpirun binds each rank to one core when it starts two or
/// fewer, to a socket beyond that, and nothing when --bind-to none.
int cpusAllowed() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return hardwareThreads();
    return std::max(1, CPU_COUNT(&set));
}

/// Threads this rank renders with: --threads; else the cores mpirun bound it to; else (not
/// bound) the node's cores shared among the ranks on it.
int threadsForRank(const RenderJob& job, const MpiTransport& t) {
    if (job.threads > 0) return job.threads;
    const int allowed = cpusAllowed();
    if (allowed < hardwareThreads()) return allowed;
    return std::max(1, hardwareThreads() / std::max(1, t.ranksOnThisNode()));
}

/// A fresh run starts from an empty frames directory: frames left by an earlier job must not be
/// mistaken for this one's by a later --resume.
void prepareFramesDir(const std::string& dir) {
    ensureWritableDir(dir);
    const bool ours = std::filesystem::exists(std::filesystem::path(dir) / "rayfarm-frames.json");
    static const std::regex framePattern(R"(frame_\d{6}\.png(\.part)?)");
    std::vector<std::filesystem::path> old;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (std::regex_match(e.path().filename().string(), framePattern)) old.push_back(e.path());
    if (!old.empty() && !ours)
        throw UsageError(dir + ": holds frame PNGs that rayfarm did not write; choose another --frames-dir");
    for (const auto& p : old) std::filesystem::remove(p);
}

/// Rank 0's part of makeJob: everything decided from the options and the loaded scene, checked
/// before any rendering.
void decideJob(RenderJob& job, const ArgParser& p, Scene& scene, int ranks, const std::string& threadsNote) {
    job.settings = scene.settings;
    applyQualityOptions(p, job.settings);
    if (job.fpsOption > 0.0) {
        const std::string ext = std::filesystem::path(job.scenePath).extension().string();
        const bool bareModel = ext == ".glb" || ext == ".gltf" || ext == ".GLB" || ext == ".GLTF";
        scene.timelineJson = timelineWithFps(scene.timelineJson, bareModel, job.fpsOption);
    }
    const anim::Timeline tl = anim::Timeline::fromScene(scene);
    resolveAutoExposure(scene, tl, job.settings, job.threads);
    job.timelineFrames = tl.frameCount();
    job.timelineFps = tl.fps();
    job.first = 0;
    job.last = job.timelineFrames - 1;
    if (auto f = p.value("--frames")) parseFrameRange(*f, job.timelineFrames, job.first, job.last);
    job.mp4.fps = tl.isStill() && job.fpsOption > 0.0 ? job.fpsOption : tl.fps();
    std::string note;
    try {
        note = checkMp4Options(job.settings.width, job.settings.height, job.mp4);
    } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
    }
    if (!note.empty()) std::cerr << "rayfarm: note: " << note << "\n";

    const int frames = job.last - job.first + 1;
    const int renderers = ranks <= 2 ? ranks : ranks - 1;
    if (job.modeOption == "auto") {
        job.mode = chooseMode(frames, renderers, job.settings.width, job.settings.height, job.modeWhy);
        job.modeWhy = "auto: " + job.modeWhy;
    } else {
        job.mode = job.modeOption == "pixel" ? Mode::Pixel : Mode::Frame;
        job.modeWhy = "as asked";
    }
    if (!job.framesDir.empty()) {
        if (job.resume) {
            checkFramesManifest(job.framesDir, job.identity());
        } else {
            prepareFramesDir(job.framesDir);
            writeFramesManifest(job.framesDir, job.identity());
        }
    }
    std::fprintf(stderr, "rayfarm: %s: frames %s of %d, %dx%d, %d spp; mode %s (%s); %d rank%s, %s\n",
                 job.scenePath.c_str(), frameSpan(job.first, job.last).c_str(), job.timelineFrames,
                 job.settings.width, job.settings.height, job.settings.spp, job.mode == Mode::Pixel ? "pixel" : "frame",
                 job.modeWhy.c_str(), ranks, ranks == 1 ? "" : "s", threadsNote.c_str());
    if (p.has("--preview")) startPreview(job.framesDir, job.last - job.first + 1);
}

struct Rank0Sinks {
    std::unique_ptr<AsyncSink> mp4, png;
    void close() {
        std::exception_ptr first;
        for (auto* s : {png.get(), mp4.get()}) {
            if (!s) continue;
            try {
                s->close();
            } catch (...) {
                if (!first) first = std::current_exception();
            }
        }
        if (first) std::rethrow_exception(first);
    }
};

int runRank0(MpiTransport& t, RenderJob& job, SharedScene& shared, const std::vector<std::string>& args,
             Clock::time_point wallStart) {
    for (const std::string& note : shared.scene.notes) std::cerr << "rayfarm: note: " << note << "\n";
    const int ranks = t.size();
    const int threads = threadsForRank(job, t);
    const int width = job.settings.width, height = job.settings.height;
    const std::vector<int> order = job.frames();
    std::set<int> kept;
    if (job.resume) {
        kept = findKeptFrames(job.framesDir, order, width, height);
        std::fprintf(stderr, "rayfarm: resume: %zu of %zu frames kept in %s, %zu to render\n", kept.size(), order.size(),
                     job.framesDir.c_str(), order.size() - kept.size());
    }
    std::vector<int> toRender;
    for (int f : order)
        if (!kept.count(f)) toRender.push_back(f);

    Rank0Sinks sinks;
    sinks.mp4 = std::make_unique<AsyncSink>(std::make_unique<Mp4Sink>(job.output, width, height, job.mp4), 4);
    if (!job.framesDir.empty())
        sinks.png = std::make_unique<AsyncSink>(std::make_unique<PngSink>(job.framesDir, width, height), 4);

    anim::Timeline timeline = anim::Timeline::fromScene(shared.scene);
    const bool rank0Renders = ranks <= 2;  // with more ranks, rank 0's core serves the master and encoder
    const int renderers = rank0Renders ? ranks : ranks - 1;
    MasterConfig cfg;
    cfg.workerTimeout = job.workerTimeout;
    // Pixel mode: a 64x64 tile renders in about a millisecond, as long as a round trip to rank 0,
    // so each rank holds more of them to never wait for the next.
    cfg.credits = job.mode == Mode::Pixel ? 4 : 2;
    cfg.liveProgress = stderrIsTerminal();
    cfg.totalFrames = int(order.size());
    std::unique_ptr<Scheduler> sched;
    if (job.mode == Mode::Pixel) {
        // Big tiles mean fewer messages; small frames still get enough tiles to keep every
        // rank's hands full.
        int tile = job.tileSize;
        while (tile > 16 && int(makeTiles(width, height, tile).size()) < 2 * renderers * cfg.credits) tile /= 2;
        const int tilesPerFrame = int(makeTiles(width, height, tile).size());
        const int window = 2 + (renderers * cfg.credits + tilesPerFrame - 1) / tilesPerFrame;
        sched = makePixelScheduler(toRender, width, height, tile, window);
    } else {
        sched = makeFrameScheduler(toRender, width, height, renderers * cfg.credits + 2);
    }
    FrameAssembler assembler(width, height, order, kept);
    std::unique_ptr<RenderEngine> local;
    if (rank0Renders) local = std::make_unique<RenderEngine>(std::move(shared.scene), timeline, job.settings, threads);

    int encodedKept = 0;
    auto emit = [&](ReadyFrame& rf) {
        if (rf.onDisk) {
            int w = 0, h = 0;
            rf.rgb = readImageRgb8(framePngPath(job.framesDir, rf.frame), w, h);
            if (w != width || h != height) throw std::runtime_error(framePngPath(job.framesDir, rf.frame) + ": wrong size");
            ++encodedKept;
        }
        sinks.mp4->write(rf.frame, rf.rgb);
    };
    Master master(t, *sched, assembler, local.get(), emit, cfg);
    if (sinks.png) master.onFrameComplete([&](int frame, const std::vector<uint8_t>& rgb) { sinks.png->write(frame, rgb); });
    MasterOutcome o;
    try {
        o = master.run();
    } catch (...) {
        master.stopWorkers();
        throw;
    }

    std::string silent;
    if (o.end == RunEnd::Interrupted) {
        // Under mpirun SIGKILL follows SIGTERM within about a second: finish the video first, and
        // meanwhile find out whether a worker's death is why we were signalled.
        std::exception_ptr closeError;
        std::thread closer([&] {
            try {
                sinks.close();
            } catch (...) {
                closeError = std::current_exception();
            }
        });
        if (ranks > 1) silent = master.findSilentWorker(0.5);
        closer.join();
        if (closeError) std::rethrow_exception(closeError);
    } else {
        try {
            sinks.close();
        } catch (...) {
            master.stopWorkers();
            throw;
        }
    }
    const auto end = Clock::now();
    local.reset();

    const int encoded = sinks.mp4->framesDone();
    const std::string what = "the video " + job.output + " holds " +
                             (encoded ? "frames " + frameSpan(job.first, job.first + encoded - 1) : std::string("no frames")) +
                             " of " + frameSpan(job.first, job.last);
    if (o.end == RunEnd::WorkerLost || !silent.empty()) {
        std::fprintf(stderr, "rayfarm: error: %s; %s (playable)\n", (silent.empty() ? o.message : silent).c_str(), what.c_str());
        if (!job.framesDir.empty())
            std::fprintf(stderr, "rayfarm: finished frames are in %s; to resume: %s\n", job.framesDir.c_str(),
                         resumeCommand(args, ranks).c_str());
        std::fflush(stderr);
        if (ranks > 1) t.abort(1);
        return 1;
    }
    if (o.end == RunEnd::Interrupted) {
        // Both lines in one write, before telling the workers (mpirun's SIGKILL is near).
        const bool sigint = interruptSignal() == SIGINT;
        std::string lines = "rayfarm: interrupted (" + std::string(sigint ? "SIGINT" : "SIGTERM") + "): " + what + " (playable)\n";
        if (!job.framesDir.empty()) lines += "rayfarm: to resume: " + resumeCommand(args, ranks) + "\n";
        writeStderr(lines);
        master.stopWorkers();
        return sigint ? 130 : 143;
    }
    master.stopWorkers();
    if (o.end == RunEnd::Failed) throw std::runtime_error(o.message + "; " + what);

    // Done.
    const double span = secondsBetween(o.firstDispatch == Clock::time_point{} ? wallStart : o.firstDispatch,
                                       std::max(sinks.mp4->lastDone(), o.firstDispatch));
    const double sustained = span > 0.0 ? encoded / span : 0.0;
    const double wall = secondsBetween(wallStart, end);
    const double encodeS = sinks.mp4->busySeconds();
    std::fprintf(stderr,
                 "rayfarm: wrote %s: %d frames %dx%d at %.4g fps; %.1f fps sustained over %.2f s (wall %.2f s); "
                 "encoder busy %.2f s (%.0f%%)\n",
                 job.output.c_str(), encoded, width, height, job.mp4.fps, sustained, span, wall, encodeS,
                 span > 0 ? 100.0 * encodeS / span : 0.0);
    if (o.rays.nonFinite)
        std::fprintf(stderr, "rayfarm: note: %llu non-finite samples replaced by black\n", (unsigned long long)o.rays.nonFinite);
    if (!job.statsPath.empty()) {
        RunStats s;
        s.frames = encoded;
        s.width = width;
        s.height = height;
        s.mode = job.mode == Mode::Pixel ? "pixel" : "frame";
        s.ranks = ranks;
        s.threadsPerRank = threads;
        s.wallSeconds = wall;
        s.sustainedFps = sustained;
        s.renderSeconds = span;
        s.encodeSeconds = encodeS;
        s.rays = o.rays;
        s.perRank = o.perRank;
        s.extra["frames_rendered"] = double(encoded - encodedKept);
        s.extra["frames_kept"] = double(encodedKept);
        s.extra["video_fps"] = job.mp4.fps;
        s.extra["encoder_share"] = span > 0 ? encodeS / span : 0.0;
        s.extra["png_s"] = sinks.png ? sinks.png->busySeconds() : 0.0;
        s.extra["load_s"] = shared.loadSeconds;
        s.extra["scene_bytes"] = double(shared.bundleBytes);
        s.extraText["mode_reason"] = job.modeWhy;
        s.extraText["rank0_renders"] = rank0Renders ? "yes" : "no";
        s.extraText["encoder"] = job.mp4.lossless ? "libx264rgb qp 0" : "libx264 crf " + std::to_string(job.mp4.crf) + " " + job.mp4.preset;
        writeStatsJson(job.statsPath, s);
    }
    return 0;
}

int runWorkerRank(MpiTransport& t, const RenderJob& job, SharedScene& shared) {
    try {
        const RenderSettings settings = decodeWorkerJob(shared.job, shared.scene.timelineJson);
        anim::Timeline timeline = anim::Timeline::fromScene(shared.scene);
        RenderEngine engine(std::move(shared.scene), timeline, settings, threadsForRank(job, t));
        // A silent master: leave now, as MPI_Finalize would wait for rank 0 forever.
        const int code = runWorker(t, engine, std::max(4.0, 2.0 * job.workerTimeout));
        if (code == kMasterSilentExit) std::_Exit(1);
        return code;
    } catch (const std::exception& e) {
        reportWorkerError(t, e.what());
        return 1;
    }
}

}  // namespace

int runRender(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        if (a == "--help" || a == "-h") {
            std::fputs(kRenderHelp, stdout);
            return 0;
        }
    const auto wallStart = Clock::now();
    MpiTransport t;
    installInterruptHandlers();
    ArgParser p("render");
    declareRenderOptions(p);
    RenderJob job;
    try {
        p.parse(args);
        job = jobFromOptions(p);
    } catch (...) {
        if (t.rank() == 0) throw;
        return 2;  // every rank parsed the same arguments; rank 0 reports
    }
    const std::string threadsNote = std::to_string(threadsForRank(job, t)) + " render thread(s) on rank 0" +
                                    (cpusAllowed() < hardwareThreads() ? " (bound by mpirun to " + std::to_string(cpusAllowed()) + " of " +
                                                                             std::to_string(hardwareThreads()) + " CPUs)"
                                                                       : "");
    SharedScene shared;
    try {
        shared = shareScene(
            t, job.scenePath,
            [&] {
                checkWritableFile(job.output);
                if (!job.statsPath.empty()) checkWritableFile(job.statsPath);
            },
            [&](Scene& scene) {
                decideJob(job, p, scene, t.size(), threadsNote);
                return encodeWorkerJob(job, scene.timelineJson);
            },
            sceneOptions(p));
    } catch (const PeerFailed& e) {
        return e.code();
    } catch (const std::exception& e) {
        if (t.rank() == 0) throw;
        reportWorkerError(t, std::string("loading the broadcast scene: ") + e.what());
        return 1;
    }
    if (t.rank() != 0) return runWorkerRank(t, job, shared);
    return runRank0(t, job, shared, args, wallStart);
}

}  // namespace rf::cli
