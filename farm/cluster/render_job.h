#pragma once
/// A render job as rank 0 decides it from the command line and the scene: quality settings,
/// frame range, mode, outputs. Rank 0 sends the part the workers need along with the scene.
#include <string>
#include <vector>

#include "engine/scene/background.h"
#include "engine/scene/scene_options.h"
#include "anim/frame_ranges.h"
#include "farm/cluster/messages.h"
#include "farm/output/video_options.h"
#include "farm/cluster/scheduler.h"
#include "engine/util/settings.h"

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
    Mp4Options mp4;              ///< the video's options, read per format by videoFormatOf
    BackgroundChoice background;  ///< --background
    /// The command line's scene options (--environment, --environment-rotation, --ground, ...),
    /// as every rank loads the scene with them: part of identity().
    SceneOptions sceneOptions;
    bool transparent = false;    ///< decided: the background is transparent (RGBA frames)
    bool exrFrames = false;      ///< --frames-format exr: linear half-float EXR frames too
    std::string contactSheet;    ///< --contact-sheet FILE.png, "" if not asked for
    std::string poster;          ///< --poster FILE.png, "" if not asked for
    int posterFrame = -1;        ///< --poster-frame (timeline index), -1: the first frame
    int threads = 0;             ///< --threads (0: share the node's cores among its ranks)
    double workerTimeout = 10.0;
    /// Ranks lost while rendering the same frame before the run gives up on it (a poison frame).
    int maxFrameFailures = 3;
    int tileSize = 128;
    int chunkFramesOption = 0;   ///< --chunk-frames, 0 if not given (mp4.chunkFrames is decided)
    /// Chunked encoding on the rendering ranks (chunksOnRenderers): decided by `render` before
    /// the job goes to the workers, which then encode too.
    bool chunkedFrames = false;

    /// The frames selected (--frames), as one range.
    anim::FrameRanges frames() const { return anim::FrameRanges::span(first, last); }
    /// How every rank lays out the pixels of this job's tiles and frames.
    PixelLayout layout() const { return {transparent ? 4 : 3, exrFrames}; }
    /// Identifies what a frames directory holds, for --resume: a JSON object of everything that
    /// changes a kept frame's pixels or which picture a frame index is (the scene file, the
    /// resolved render settings, the timeline, the scene options, the frames' formats); the
    /// input files' contents are in the manifest's digests beside it. A setting at its default
    /// is left out where earlier manifests did not have it, so their frames still resume.
    /// render_identity_test checks that every render option is either here or changes no pixel.
    std::string identity() const;
};

/// What shapes the workers' results beyond the render settings: the background and whether
/// the linear plane (EXR frames) is wanted. Trivially copyable: it travels as bytes.
struct WorkerOutputs {
    BackgroundChoice background;
    int32_t linear = 0;
};
/// Whether this job's chunks are encoded by one rank each, which renders them (frame mode) or
/// assembles them from every rank's tiles (pixel mode): a video joined from chunks (MP4, WebM,
/// MOV); not a GIF, whose palette needs the whole film on rank 0, nor EXR frames, whose linear
/// pixels rank 0 writes.
bool chunksOnRenderers(const RenderJob& j);

/// How the job's chunks are encoded, for the ranks that encode them.
struct ChunkVideoSpec;
ChunkVideoSpec chunkVideoSpec(const RenderJob& j);

/// What the workers need beyond the scene bundle and the options every rank parsed (the render
/// settings rank 0 settled on, the outputs' pixel needs, and with chunkedFrames the video's
/// encoding), as bytes for the scene broadcast, and back. outputs (if given) gets the
/// WorkerOutputs; chunkVideo (if given) the encoded ChunkVideoSpec, "" when ranks do not encode.
std::string encodeWorkerJob(const RenderJob& j);
RenderSettings decodeWorkerJob(const std::string& bytes, WorkerOutputs* outputs = nullptr, std::string* chunkVideo = nullptr);

}  // namespace rf::farm
