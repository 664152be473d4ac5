// rayfarm render: the timeline to an MP4, as one process or as an MPI farm. This file wires the
// parts together; scheduling, messages, sinks and the loops live in their own files.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sched.h>

#include "farm/cli/background_option.h"
#include "engine/integrators/bounce_cache.h"
#include "farm/cli/cli.h"
#include "engine/util/errors.h"
#include "farm/cli/exposure_meter.h"
#include "farm/output/gif_sink.h"
#include "farm/process/interrupt.h"
#include "farm/cli/launch_command.h"
#include "farm/process/load_watch.h"
#include "farm/cluster/master.h"
#include "farm/output/output_check.h"
#include "farm/output/output_lock.h"
#include "farm/output/output_paths.h"
#include "engine/util/parallel.h"
#include "farm/output/png_sink.h"
#include "farm/cli/preview_spawn.h"
#include "farm/process/progress.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "farm/cli/render_options.h"
#include "farm/output/run_stats.h"
#include "farm/cluster/run_farm.h"
#include "farm/cluster/scene_broadcast.h"
#include "anim/timeline.h"
#include "farm/cluster/transport.h"
#include "farm/process/usage_error.h"
#include "farm/output/video_format.h"
#include "farm/cluster/worker.h"

namespace rf::cli {

using namespace rf::farm;
using Clock = std::chrono::steady_clock;

namespace {

/// printf into a std::string of whatever length it takes (scene paths have no limit).
template <class... A>
std::string formatted(const char* fmt, A... a) {
    const int n = std::snprintf(nullptr, 0, fmt, a...);
    std::string s(size_t(std::max(n, 0)) + 1, '\0');
    std::snprintf(s.data(), s.size(), fmt, a...);
    s.resize(size_t(std::max(n, 0)));
    return s;
}

/// How this executable was invoked (argv[0]), for the resume hint.
std::string invokedAs() {
    std::ifstream f("/proc/self/cmdline", std::ios::binary);
    std::string arg0;
    std::getline(f, arg0, '\0');
    return arg0.empty() ? "rayfarm" : arg0;
}

std::string resumeCommand(const std::vector<std::string>& args, int ranks) {
    // Under mpirun, mpirun's own options (--oversubscribe, --hostfile, --mca ...) come along.
    const std::string launcher = launcherPrefix(ranks);
    std::string cmd = (launcher.empty() ? std::string() : launcher + " ") + shellQuote(invokedAs()) + " render";
    bool hasResume = false;
    for (const std::string& a : args) {
        if (a == "--overwrite") continue;  // it would throw away the frames the resume keeps
        cmd += ' ';
        cmd += shellQuote(a);
        hasResume = hasResume || a == "--resume";
    }
    return hasResume ? cmd : cmd + " --resume";
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
int threadsForRank(const RenderJob& job, const Transport& t) {
    if (job.threads > 0) return job.threads;
    const int allowed = cpusAllowed();
    if (allowed < hardwareThreads()) return allowed;
    return std::max(1, hardwareThreads() / std::max(1, t.ranksOnThisNode()));
}

/// "2 render thread(s) on rank 0 (bound by mpirun to 1 of 2 CPUs)", for the plan line.
std::string describeThreads(const RenderJob& job, const Transport& t) {
    std::string s = std::to_string(threadsForRank(job, t)) + " render thread(s) on rank 0";
    if (cpusAllowed() < hardwareThreads())
        s += " (bound by mpirun to " + std::to_string(cpusAllowed()) + " of " + std::to_string(hardwareThreads()) + " CPUs)";
    return s;
}

/// The outputs' part of decideJob: the background (the scene's transparency decides the frames'
/// alpha), the video format from the output's name and the options, the poster's frame.
void decideOutputs(RenderJob& job, Scene& scene) {
    applyBackground(job.background, scene);
    job.transparent = scene.transparentBackground;
    job.mp4.channels = job.layout().channels;
    if (job.posterFrame >= 0 && (job.posterFrame < job.first || job.posterFrame > job.last))
        throw UsageError("--poster-frame: expected a frame from " + std::to_string(job.first) + " to " + std::to_string(job.last));
    std::string note;
    try {
        videoFormatOf(job.output, job.mp4);  // throws on what the format cannot do
        note = checkMp4Options(job.settings.width, job.settings.height, job.mp4, job.output);
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();  // an option's own error leads with the option
        throw UsageError(what.rfind("--", 0) == 0 ? what : job.output + ": " + what);
    }
    if (!note.empty()) printLine("note", note);
}

/// Every file the render writes, by the option that names it (for checkOutputPaths).
std::vector<NamedOutput> renderOutputs(const RenderJob& job) {
    return {{"-o", job.output}, {"--frames-dir", job.framesDir}, {"--stats", job.statsPath},
            {"--contact-sheet", job.contactSheet}, {"--poster", job.poster}};
}

/// Rank 0 before the scene is read: the outputs can be written, name no input and no other
/// output, and no other run writes them (the locks, held until the run ends); an earlier run's
/// frames are not thrown away unasked.
void claimOutputs(const RenderJob& job, const ArgParser& p, std::vector<OutputLock>& locks) {
    std::vector<std::string> inputs = {job.scenePath};
    if (auto env = p.value("--environment")) inputs.push_back(*env);
    checkOutputPaths(renderOutputs(job), inputs);
    checkWritableFile(job.output);
    if (containerFor(job.output) == Container::Gif) requireGifFilters(job.output);
    for (const std::string* f : {&job.statsPath, &job.contactSheet, &job.poster})
        if (!f->empty()) checkWritableFile(*f);
    for (const std::string* f : {&job.output, &job.framesDir}) {
        if (f->empty()) continue;
        std::string note;
        locks.emplace_back(*f, &note);
        if (!note.empty()) printLine("note", note);
    }
    if (!job.framesDir.empty() && !job.resume && !p.has("--overwrite")) refuseEarlierFrames(job.framesDir);
}

/// How the video is encoded, for the plan line.
std::string videoChunksNote(const RenderJob& job) {
    if (containerFor(job.output) == Container::Gif) return "the GIF made on rank 0 from the whole film";
    const std::string k = std::to_string(job.mp4.chunkFrames);
    if (!job.chunkedFrames) return "video in chunks of " + k + " frames encoded on rank 0";
    return job.mode == Mode::Frame ? "video in chunks of " + k + " frames, each rendered and encoded by one rank (the last frames shared)"
                                   : "video in chunks of " + k + " frames, each assembled from the tiles and encoded by one rank";
}

/// Builds the scene's bounce cache for these settings at `frame`, on a posed copy (posing leaves
/// traces in a scene, as resolveAutoExposure says), so that the film's first frame on this rank
/// finds it ready instead of building it inside the run (about 0.4 s on one core for
/// 2CylinderEngine) into the film's slot; a cache for other settings or another pose
/// is simply not used, and the render builds its own as before.
void prebuildBounceCache(const Scene& scene, const anim::Timeline& tl, const RenderSettings& settings, int frame,
                         int threads, SceneCacheSlot& bounceSlot) {
    if (settings.bounce <= 0 || !bounceApplies(scene)) return;
    Scene posed = scene;
    tl.applyFrame(posed, frame);
    bounceCache(posed, settings, &bounceSlot, threads > 0 ? threads : hardwareThreads());
}

/// A worker's head start (shareScene) while rank 0 decides the job and meters its exposure: the
/// bounce cache for the settings and first frame the same command line gives rank 0.
void workerHeadStart(Scene& scene, SceneCacheSlot& bounceSlot, const ArgParser& p, const RenderJob& job, int threads) {
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    const anim::Timeline tl = anim::Timeline::fromScene(scene, job.fpsOption);
    int first = 0, last = tl.frameCount() - 1;
    if (auto f = p.value("--frames")) parseFrameRange(*f, tl.frameCount(), first, last);
    prebuildBounceCache(scene, tl, settings, first, threads, bounceSlot);
}

/// Rank 0's part of makeJob: everything decided from the options and the loaded scene, checked
/// before any rendering.
void decideJob(RenderJob& job, const ArgParser& p, Scene& scene, const std::shared_ptr<SceneCacheSlot>& bounceSlot,
               const FileBundle& inputs, int ranks, const std::string& threadsNote, bool filmOfSeveral) {
    job.settings = scene.settings;
    applyQualityOptions(p, job.settings);
    const anim::Timeline tl = anim::Timeline::fromScene(scene, job.fpsOption);
    job.timelineFrames = tl.frameCount();
    job.timelineFps = tl.fps();
    job.first = 0;
    job.last = job.timelineFrames - 1;
    if (auto f = p.value("--frames")) parseFrameRange(*f, job.timelineFrames, job.first, job.last);
    job.mp4.fps = tl.isStill() && job.fpsOption > 0.0 ? job.fpsOption : tl.fps();
    job.mp4.chunkFrames =
        job.chunkFramesOption > 0 ? job.chunkFramesOption : defaultChunkFrames(job.mp4.fps, job.last - job.first + 1);
    decideOutputs(job, scene);
    // Metering renders: only once every option has been checked. When rank 0 renders (two ranks
    // or fewer), the bounce cache first, at the first frame, as the workers build theirs
    // meanwhile (workerHeadStart); the meter uses it.
    if (ranks <= 2) prebuildBounceCache(scene, tl, job.settings, job.first, job.threads, *bounceSlot);
    resolveAutoExposure(scene, tl, job.settings, job.threads, {}, bounceSlot);
    // A format without alpha lays the frames over the background colour, as the scene shows it.
    const float bg[3] = {scene.background.r, scene.background.g, scene.background.b};
    encodeRgb8(bg, 3, job.settings.toneMap, job.mp4.flattenOver, exposureScale(job.settings.exposure));

    const int frames = job.last - job.first + 1;
    const int renderers = ranks <= 2 ? ranks : ranks - 1;
    if (job.modeOption == "auto") {
        // Chunks are encoded on the rendering ranks unless rank 0 needs every frame's pixels (a
        // GIF, EXR frames).
        const int chunkFrames = chunksOnRenderers(job) ? job.mp4.chunkFrames : 1;
        job.mode = chooseMode(frames, renderers, job.settings.width, job.settings.height, job.modeWhy, chunkFrames);
        job.modeWhy = "auto: " + job.modeWhy;
    } else {
        job.mode = job.modeOption == "pixel" ? Mode::Pixel : Mode::Frame;
        job.modeWhy = "as asked";
    }
    job.chunkedFrames = chunksOnRenderers(job);
    if (!job.framesDir.empty()) {
        // In a job of several films --resume applies film by film: one never started starts now.
        if (job.resume && filmOfSeveral && !std::filesystem::exists(std::filesystem::path(job.framesDir) / "rayfarm-frames.json")) {
            printLine("note", job.framesDir + ": nothing kept for this film yet; rendering it whole");
            job.resume = false;
        }
        if (job.resume) {
            checkFramesManifest(job.framesDir, job.identity(), inputDigests(inputs));
        } else {
            prepareFramesDir(job.framesDir);
            writeFramesManifest(job.framesDir, job.identity(), inputDigests(inputs));
        }
    }
    const std::string plan =
        formatted("rayfarm: %s: frames %s of %d, %dx%d, %d spp; mode %s (%s); %d rank%s, %s; %s\n", printable(job.scenePath).c_str(),
                  frameSpan(job.first, job.last).c_str(), job.timelineFrames, job.settings.width, job.settings.height,
                  job.settings.spp, job.mode == Mode::Pixel ? "pixel" : "frame", job.modeWhy.c_str(), ranks, ranks == 1 ? "" : "s",
                  threadsNote.c_str(), videoChunksNote(job).c_str());
    writeStderrText(plan);
    if (!job.framesDir.empty()) appendFramesLog(job.framesDir, plan);
    if (p.has("--preview")) startPreview(job.framesDir, job.last - job.first + 1);
}

/// An interrupted run's ending, beside the outputs: the lines in the frames directory's log, and
/// the stats file (if asked for) with what was done, the signal and the resume command.
void recordInterruption(const RenderJob& job, const FarmOutcome& o, int sig, const std::string& resume, const std::string& lines) {
    if (!job.framesDir.empty()) appendFramesLog(job.framesDir, lines);
    if (job.statsPath.empty()) return;
    RunStats s = o.stats;
    s.width = job.settings.width;
    s.height = job.settings.height;
    if (s.mode.empty()) s.mode = job.mode == Mode::Pixel ? "pixel" : "frame";
    s.extraText["interrupted"] = signalName(sig);
    s.extraText["video"] = o.videoHolds;
    if (!resume.empty()) s.extraText["resume"] = resume;
    try {
        writeStatsJson(job.statsPath, s);
    } catch (const std::exception& e) {
        writeStderrText(std::string("rayfarm: error: ") + e.what() + "\n");
    }
}

/// Prints how the run ended (the lines the shell tests and users read); returns the exit status.
int reportOutcome(int ranks, const RenderJob& job, const FarmOutcome& o, const std::vector<std::string>& args) {
    if (o.end == FarmEnd::WorkerLost) {
        std::string lines = "rayfarm: error: " + o.error + "; " + o.videoHolds + " (playable)\n";
        if (!job.framesDir.empty())
            lines += "rayfarm: finished frames are in " + job.framesDir + "; to resume: " + resumeCommand(args, ranks) + "\n";
        writeStderrText(lines);
        if (!job.framesDir.empty()) appendFramesLog(job.framesDir, lines);
        return 1;
    }
    if (o.end != FarmEnd::Done) {
        // Both lines in one write, before runFarm tells the workers (mpirun's SIGKILL is near).
        const int sig = o.signal ? o.signal : SIGTERM;
        std::string lines = "rayfarm: interrupted (" + signalName(sig) + "): " + o.videoHolds + " (playable)\n";
        if (!job.framesDir.empty()) lines += "rayfarm: to resume: " + resumeCommand(args, ranks) + "\n";
        writeStderrText(lines);
        // Also where it can be read when stderr is gone (a hang-up, a closed pipe).
        recordInterruption(job, o, sig, job.framesDir.empty() ? "" : resumeCommand(args, ranks), lines);
        return signalExitStatus(sig);
    }
    const RunStats& s = o.stats;
    std::string lines = formatted("rayfarm: wrote %s: %d frames %dx%d at %.4g fps; %.1f fps sustained over %.2f s (wall %.2f s); "
                                  "encoder busy %.2f s (%.0f%%)\n",
                                  printable(job.output).c_str(), s.frames, s.width, s.height, job.mp4.fps, s.sustainedFps, s.renderSeconds,
                                  s.wallSeconds, s.encodeSeconds, s.renderSeconds > 0 ? 100.0 * s.encodeSeconds / s.renderSeconds : 0.0);
    if (s.rays.nonFinite)
        lines += "rayfarm: note: " + std::to_string((unsigned long long)s.rays.nonFinite) + " non-finite samples replaced by black\n";
    writeStderrText(lines);
    if (!job.framesDir.empty()) appendFramesLog(job.framesDir, lines);
    return 0;
}

/// Rank 0 after the scene is shared: runFarm with the job's sinks, then the outcome's lines. It
/// takes the MPI transport for abort(): a lost worker cannot be stopped any other way.
int runRank0(MpiTransport& t, const RenderJob& job, SharedScene& shared, const std::vector<std::string>& args,
             Clock::time_point wallStart, const std::string& progressLabel) {
    for (const std::string& note : shared.scene.notes) printLine("note", note);  // one write() a line: mpirun interleaves ranks by write
    if (bounceLeftOutForMotion(shared.scene, job.settings))
        printLine("note", "bounce light left out: the model's geometry moves over the film, and its bounce cache would be "
                          "built again for every frame (--bounce N keeps it, at that cost)");
    FarmOptions opts;
    opts.threads = threadsForRank(job, t);
    opts.liveProgress = stderrIsTerminal();
    opts.wallStart = wallStart;
    opts.progressLabel = progressLabel;
    int code = 0;
    opts.onEnd = [&](const FarmOutcome& o) { code = reportOutcome(t.size(), job, o, args); };
    StopWorkersOnThrow setUp(t);  // opening the video can fail (a full disk), after the workers started
    const anim::Timeline timeline = anim::Timeline::fromScene(shared.scene, job.fpsOption);
    FarmSinks sinks = sinksForJob(job, [timeline](int f) { return timeline.frameTime(f); });
    setUp.dismiss();  // runFarm guards its own set-up
    FarmOutcome o;
    try {
        o = runFarm(t, job, shared, std::move(sinks), opts);
    } catch (const std::exception& e) {
        // A failed write (a full disk) keeps the frames done so far: say how to go on.
        if (job.framesDir.empty()) throw;
        throw std::runtime_error(std::string(e.what()) + "; finished frames are in " + job.framesDir +
                                 "; to resume: " + resumeCommand(args, t.size()));
    }
    if (o.abortRanks) t.abort(code);  // a lost worker cannot be stopped politely, and mpirun waits for it
    return code;
}

}  // namespace

/// Where a film stands in a job of several (null: a job of one film).
struct FilmInJob {
    int index = 0, count = 1;
};

/// One film on every rank: the scene shared, the job decided, rank 0's farm or a worker's loop.
/// Returns the exit status (rank 0 may throw instead, as a job of one film has always done).
int renderFilm(MpiTransport& t, const ArgParser& p, const std::vector<std::string>& args, RenderJob job,
               Clock::time_point wallStart, const FilmInJob* film) {
    const std::string threadsNote = describeThreads(job, t);
    SharedScene shared;
    // The film's bounce cache: the head start and the metering fill it, the frames use it.
    const auto bounceSlot = std::make_shared<SceneCacheSlot>();
    std::vector<OutputLock> locks;  // rank 0's, until the film ends
    locks.reserve(2);               // never moved: the load watch may release them from its thread
    try {
        // A signal while loading ends the run within a second (load_watch.h).
        LoadWatch watch(job.scenePath, t.rank() == 0, [&locks] {
            for (OutputLock& l : locks) l.release();
        });
        try {
            shared = shareScene(
                t, job.scenePath, [&] { claimOutputs(job, p, locks); },
                [&](Scene& scene, const FileBundle& inputs) {
                    std::vector<std::string> read;
                    for (const auto& [path, bytes] : inputs.files) read.push_back(path);
                    checkOutputPaths(renderOutputs(job), read);  // the model's buffers and textures too
                    decideJob(job, p, scene, bounceSlot, inputs, t.size(), threadsNote, film != nullptr);
                    return encodeWorkerJob(job);
                },
                sceneOptions(p),
                [&](Scene& scene) { workerHeadStart(scene, *bounceSlot, p, job, threadsForRank(job, t)); }, bounceSlot);
        } catch (const LoadCancelled& c) {
            const int code = watch.interrupted(c);
            // A worker gets here only when rank 0 loaded and waits for it: say why it will not hear.
            if (t.rank() != 0) reportWorkerError(t, "interrupted (" + signalName(c.signal) + ") while loading its scene");
            return code;
        }
        watch.done();
    } catch (const PeerFailed& e) {
        // Rank 0 failed (and said why), or was interrupted while loading as this rank was.
        if (loadCancelSignal()) return signalExitStatus(loadCancelSignal());
        return e.code();
    } catch (const std::exception& e) {
        if (t.rank() == 0) throw;
        reportWorkerError(t, std::string("loading the broadcast scene: ") + e.what());
        return 1;
    }
    if (t.rank() != 0) {
        const int code = runFarmWorker(t, shared, job.fpsOption, threadsForRank(job, t), std::max(4.0, 2.0 * job.workerTimeout));
        // A silent master: leave now, as MPI_Finalize would wait for rank 0 forever.
        if (code == kMasterSilentExit) std::_Exit(1);
        return code;
    }
    std::string label;
    if (film) label = "film " + std::to_string(film->index + 1) + " of " + std::to_string(film->count) + ", " + filmName(job.scenePath);
    return runRank0(t, job, shared, args, wallStart, label);
}

/// Several films as one job on the same ranks, one after another: each scene is shared once
/// with every rank, each film has its own outputs, locks, frames directory and resume. A film
/// that fails (a broken model, an output that cannot be written, a worker's error) is named and
/// the job goes on with the next; a signal or a lost rank ends the job as it ends one film.
int renderJobOfFilms(MpiTransport& t, const ArgParser& p, const std::vector<std::string>& args, const std::vector<RenderJob>& jobs) {
    const int n = int(jobs.size());
    std::vector<std::string> failed;
    bool onlyInputErrors = true;
    int written = 0;
    for (int i = 0; i < n; ++i) {
        const RenderJob& job = jobs[size_t(i)];
        if (t.rank() == 0)
            writeStderrText(formatted("rayfarm: film %d of %d: %s -> %s\n", i + 1, n, job.scenePath.c_str(), job.output.c_str()));
        const FilmInJob film{i, n};
        int code = 0;
        try {
            code = renderFilm(t, p, args, job, Clock::now(), &film);
        } catch (const InputError& e) {
            printLine("error", e.what());
            code = 2;
        } catch (const UsageError& e) {
            printLine("error", e.what());
            code = 2;
        } catch (const std::exception& e) {
            printLine("error", e.what());
            code = 1;
        }
        if (t.rank() != 0) {
            if (code == 130) return code;  // a signal: the job ends
            // A failure this rank told rank 0 of: rank 0's word to stop that film comes next.
            if (code == 1) awaitStop(t, std::max(4.0, 2.0 * job.workerTimeout));
            continue;
        }
        if (code == 0) {
            ++written;
            continue;
        }
        if (code > 128) {  // interrupted: the films after it were not started
            writeStderrText(formatted("rayfarm: job interrupted in film %d of %d (%s); %d written before it\n", i + 1, n,
                                      job.scenePath.c_str(), written));
            return code;
        }
        failed.push_back(job.scenePath);
        onlyInputErrors = onlyInputErrors && code == 2;
    }
    if (t.rank() != 0) return 0;
    std::string summary = formatted("rayfarm: job of %d films: %d written", n, written);
    if (!failed.empty()) {
        summary += "; failed: ";
        for (size_t i = 0; i < failed.size(); ++i) {
            if (i) summary += ", ";
            summary += failed[i];
        }
    }
    writeStderrText(summary + "\n");
    return failed.empty() ? 0 : onlyInputErrors ? 2 : 1;
}

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
    std::vector<RenderJob> jobs;
    try {
        p.parse(args);
        jobs = jobsFromOptions(p);
    } catch (...) {
        if (t.rank() == 0) throw;
        return 2;  // every rank parsed the same arguments; rank 0 reports
    }
    if (jobs.size() == 1) return renderFilm(t, p, args, jobs[0], wallStart, nullptr);
    return renderJobOfFilms(t, p, args, jobs);
}

}  // namespace rf::cli
