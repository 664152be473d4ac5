#pragma once
/// A render job as rank 0 decides it from the command line and the scene: quality settings,
/// frame range, mode, outputs. Rank 0 sends the part the workers need along with the scene.
#include <string>
#include <vector>

#include "background_option.h"
#include "cli.h"
#include "messages.h"
#include "mp4_sink.h"
#include "scheduler.h"
#include "settings.h"

namespace rf::farm {

struct RenderJob {
    std::string scenePath;
    std::string output;          ///< the video (.mp4, .webm, .mov, .gif)
    std::string framesDir;       ///< "" with --no-frames
    std::string statsPath;
    RenderSettings settings;
    int first = 0, last = 0;     ///< frame range, inclusive
    int timelineFrames = 1;
    double timelineFps = 30.0;
    double fpsOption = 0.0;      ///< --fps, 0 if not given
    std::string modeOption = "auto";
    Mode mode = Mode::Frame;
    std::string modeWhy;
    bool resume = false;
    Mp4Options mp4;              ///< the video's options (all containers but GIF)
    VideoFormat video;           ///< what the output's name and the options chose
    cli::BackgroundChoice background;  ///< --background
    bool transparent = false;    ///< decided: the background is transparent (RGBA frames)
    bool exrFrames = false;      ///< --frames-format exr: linear half-float EXR frames too
    std::string contactSheet;    ///< --contact-sheet FILE.png, "" if not asked for
    std::string poster;          ///< --poster FILE.png, "" if not asked for
    int posterFrame = -1;        ///< --poster-frame (timeline index), -1: the first frame
    int threads = 0;             ///< --threads (0: share the node's cores among its ranks)
    double workerTimeout = 10.0;
    int tileSize = 128;          ///< pixel mode's work-item size (split again into 16x16 on the rank)

    std::vector<int> frames() const;
    /// How every rank lays out the pixels of this job's tiles and frames.
    PixelLayout layout() const { return {transparent ? 4 : 3, exrFrames}; }
    /// Identifies what a frames directory holds, for --resume.
    std::string identity() const;
};

/// Declares render's options on p.
void declareRenderOptions(cli::ArgParser& p);
extern const char* kRenderHelp;

/// The options that do not need the scene (paths, mode, encoder); throws cli::UsageError.
RenderJob jobFromOptions(const cli::ArgParser& p);
/// Parses "A:B", "A:", ":B" or "A" against a timeline of n frames (inclusive, 0-based).
void parseFrameRange(const std::string& text, int n, int& first, int& last);

/// What the workers need (settings, the timeline as rank 0 adjusted it), as bytes for the scene
/// broadcast, and back.
std::string encodeWorkerJob(const RenderJob& j, const std::string& timelineJson);
/// outputs (if given) gets what shapes the workers' results: the background and whether the
/// linear plane is wanted.
struct WorkerOutputs {
    cli::BackgroundChoice background;
    int32_t linear = 0;
};
RenderSettings decodeWorkerJob(const std::string& bytes, std::string& timelineJson, WorkerOutputs* outputs = nullptr);

/// The scene's timeline section with its frame rate set to fps (--fps): frames are sampled at
/// that rate. A bare model's default turntable gets {"turntable": {"fps": fps}}.
std::string timelineWithFps(const std::string& timelineJson, bool bareModel, double fps);

}  // namespace rf::farm
