#pragma once
/// The farm's entry point: one call that renders a decided job on every rank a Transport
/// reaches and delivers the frames, in order, to its sinks. `rayfarm render` parses arguments,
/// calls it and prints the outcome; a viewer calls the same functions for a film render, with a
/// progress callback and a cancel flag instead of a terminal and Ctrl-C.
///
/// The run, as the parts see it:
///   every rank:  shareScene (scene_broadcast.h) → rank 0 decides the RenderJob
///   rank 0:      runFarm(transport, job, shared, sinks, options) → FarmOutcome
///   other ranks: runFarmWorker(transport, shared, fps, threads) → exit status
/// runFarm keeps the workers' loops running until it returns; after it, they have left them
/// (told to stop, or the outcome asks the caller to abort them).
///
/// Interactive frames go through the same call: with FarmOptions::views it runs a session
/// (view_session.h) that renders the views a window posts, each camera change an epoch of its
/// own (kTagView) that cancels older work on every rank; the workers are the same.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "farm/cluster/farm_options.h"
#include "farm/output/frame_sink.h"
#include "farm/cluster/render_job.h"
#include "farm/output/run_stats.h"
#include "farm/cluster/scene_broadcast.h"
#include "farm/cluster/transport.h"
#include "farm/cluster/view_session.h"

namespace rf::farm {

/// Where finished frames go. runFarm runs each sink on a thread of its own behind a short queue.
struct FarmSinks {
    /// every frame in output order (the MP4), or, in frame mode with chunked encoding, every
    /// chunk encoded where it was rendered (FrameSink::writeChunk); required
    std::unique_ptr<FrameSink> video;
    /// the frames each wants (FrameSink::wants) in output order: the contact sheet, the poster; optional
    std::unique_ptr<FrameSink> pictures;
    std::unique_ptr<FrameSink> frames;  ///< each frame as soon as it is complete (PNG frames); optional
};

/// The sinks a job names: the video at job.output in the format its name picked (MP4, WebM,
/// MOV: Mp4Sink; GIF: GifSink), the contact sheet and the poster as pictures; when job.framesDir is set, the PNG frames (and with --frames-format exr the EXR
/// frames) as frames complete. frameTime: a frame's time in seconds for the contact sheet's
/// labels (unset: frame / fps). Opens the encoder, so it throws what the sink throws on an
/// unwritable output.
FarmSinks sinksForJob(const RenderJob& job, std::function<double(int)> frameTime = nullptr);

/// Frames of the job already finished in its frames directory: the PNG (with the job's
/// channels, its checksum as recorded) and, with EXR frames, the EXR too. corrupt: as for
/// findKeptFrames.
anim::FrameRanges keptFramesForJob(const RenderJob& job, std::vector<int>* corrupt = nullptr);

/// Frames as the messages name them: "7" or "0–11".
std::string frameSpan(int first, int last);

/// Rank 0: renders job.frames() (those missing from the frames directory with job.resume) on
/// every rank of t and writes them to sinks. shared is the scene as shareScene delivered it;
/// its scene is moved into rank 0's renderer. Writes job.statsPath when the run is done.
FarmOutcome runFarm(Transport& t, const RenderJob& job, SharedScene& shared, FarmSinks sinks, const FarmOptions& opts);

/// Ranks 1…N−1: builds the renderer from the broadcast scene and job and serves rank 0 until
/// it says stop. Returns runWorker's status (0, 1 after a failure told to rank 0, 130 on a
/// signal, kMasterSilentExit when rank 0 was silent for masterTimeout seconds, or for
/// firstWordTimeout before its first word: runWorker).
/// fpsOption is --fps as every rank parsed it (0: the scene's own).
int runFarmWorker(Transport& t, SharedScene& shared, double fpsOption, int threads, double masterTimeout,
                  double firstWordTimeout = 0.0);

}  // namespace rf::farm
