#include "farm/commands/render_decision.h"

#include <filesystem>
#include <stdexcept>

#include "farm/cli/background_option.h"
#include "farm/cli/exposure_meter.h"
#include "farm/commands/formatted.h"
#include "farm/commands/preview_spawn.h"
#include "farm/commands/render_options.h"
#include "farm/commands/worker_head_start.h"
#include "engine/util/errors.h"
#include "engine/util/image.h"
#include "farm/output/gif_sink.h"
#include "farm/output/output_check.h"
#include "farm/output/png_sink.h"
#include "farm/output/run_files.h"
#include "farm/output/video_format.h"
#include "farm/output/video_options.h"
#include "farm/process/interrupt.h"
#include "farm/process/usage_error.h"
#include "farm/cluster/run_farm.h"
#include "farm/cluster/scheduler.h"
#include "anim/timeline.h"

namespace rf::cli {

using namespace rf::farm;

namespace {

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
    int videoW = 0, videoH = 0;
    mp4EncodedSize(job.settings.width, job.settings.height, job.mp4, videoW, videoH, job.output);
    if (!job.framesDir.empty() && (videoW != job.settings.width || videoH != job.settings.height))
        note += "; the kept frames are " + std::to_string(job.settings.width) + "x" + std::to_string(job.settings.height);
    if (!note.empty()) printLine("note", note);
}

/// How the video is encoded, for the plan line.
std::string videoChunksNote(const RenderJob& job) {
    if (containerFor(job.output) == Container::Gif) return "the GIF made on rank 0 from the whole film";
    const std::string k = std::to_string(job.mp4.chunkFrames);
    if (!job.chunkedFrames) return "video in chunks of " + k + " frames encoded on rank 0";
    return job.mode == Mode::Frame ? "video in chunks of " + k + " frames, each rendered and encoded by one rank (the last frames shared)"
                                   : "video in chunks of " + k + " frames, each assembled from the tiles and encoded by one rank";
}

}  // namespace

std::vector<NamedOutput> renderOutputs(const RenderJob& job) {
    return {{"-o", job.output}, {"--frames-dir", job.framesDir}, {"--stats", job.statsPath},
            {"--contact-sheet", job.contactSheet}, {"--poster", job.poster}};
}

void claimOutputs(const RenderJob& job, const ArgParser& p, std::vector<OutputLock>& locks) {
    std::vector<std::string> inputs = {job.scenePath};
    if (auto env = p.value("--environment")) inputs.push_back(*env);
    checkOutputPaths(renderOutputs(job), inputs);
    checkOutputsAgainstRunFiles(renderOutputs(job), job.output, job.framesDir);
    checkWritableFile(job.output);
    if (containerFor(job.output) == Container::Gif) requireGifFilters(job.output);
    for (const std::string* f : {&job.statsPath, &job.contactSheet, &job.poster})
        if (!f->empty()) checkWritableFile(*f);
    if (!job.framesDir.empty()) ensureParentDir(job.framesDir);  // its lock lies beside it
    for (const std::string* f : {&job.output, &job.framesDir}) {
        if (f->empty()) continue;
        std::string note;
        locks.emplace_back(*f, &note);
        if (!note.empty()) printLine("note", note);
    }
    if (!job.framesDir.empty() && !job.resume && !p.has("--overwrite")) refuseEarlierFrames(job.framesDir);
}

void decideJob(RenderJob& job, const ArgParser& p, LoadedScene& loaded, const std::shared_ptr<SceneCacheSlot>& bounceSlot,
               const FileBundle& inputs, int ranks, const std::string& threadsNote, bool filmOfSeveral) {
    Scene& scene = loaded.scene;
    job.settings = scene.settings;
    applyQualityOptions(p, job.settings);
    const anim::Timeline tl = anim::Timeline::fromScene(loaded, job.fpsOption);
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

}  // namespace rf::cli
