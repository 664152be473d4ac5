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

#include "frame_sink.h"
#include "render_job.h"
#include "run_stats.h"
#include "scene_broadcast.h"
#include "transport.h"
#include "view_session.h"

namespace rf::farm {

/// Where finished frames go. runFarm runs each sink on a thread of its own behind a short queue.
struct FarmSinks {
    std::unique_ptr<FrameSink> video;   ///< every frame in output order (the MP4); required
    std::unique_ptr<FrameSink> frames;  ///< each frame as soon as it is complete (PNG frames); optional
};

/// The sinks a job names: the video at job.output in the format its name picked (MP4, WebM,
/// MOV: Mp4Sink; GIF: GifSink), with the contact sheet and the poster beside it in output
/// order; when job.framesDir is set, the PNG frames (and with --frames-format exr the EXR
/// frames) as frames complete. frameTime: a frame's time in seconds for the contact sheet's
/// labels (unset: frame / fps). Opens the encoder, so it throws what the sink throws on an
/// unwritable output.
FarmSinks sinksForJob(const RenderJob& job, std::function<double(int)> frameTime = nullptr);

/// Frames of the job already finished in its frames directory: the PNG (with the job's
/// channels, its checksum as recorded) and, with EXR frames, the EXR too. corrupt: as for
/// findKeptFrames.
std::set<int> keptFramesForJob(const RenderJob& job, std::vector<int>* corrupt = nullptr);

/// One frame passed on to the video sink, in output order.
struct FarmProgress {
    int frame = -1;                          ///< its timeline index
    int framesDone = 0;                      ///< frames passed on so far, kept frames included
    int framesTotal = 0;                     ///< frames in the output
    bool kept = false;                       ///< read back from the frames directory (--resume)
    /// The frame in the job's PixelLayout (width × height × 3 sRGB bytes, or straight RGBA with a
    /// transparent background, then the linear plane with EXR frames), valid during the call.
    const std::vector<uint8_t>* rgb = nullptr;
    /// An interactive session's picture (then rgb is view->size.width × height pixels): which
    /// view and pass it is. Null for the frames of a job.
    const ViewPicture* view = nullptr;
};

struct FarmOutcome;

/// How a caller steers a run. Callbacks run on the calling thread (the one that owns the
/// transport), between scheduling steps, so they must be short: a long one delays work for
/// every rank.
struct FarmOptions {
    int threads = 1;  ///< render threads of rank 0 when it renders too (three ranks or fewer)
    /// Called after each frame goes to the video sink.
    std::function<void(const FarmProgress&)> onFrame;
    /// When it reads true, the run winds down as on SIGINT: outstanding work is dropped, the
    /// video is closed holding every frame done so far, and the outcome is Cancelled.
    const std::atomic<bool>* cancel = nullptr;
    /// Lines worth telling the user ("resume: 9 of 12 frames kept ..."), without the "rayfarm: "
    /// prefix. Unset: printed on stderr with it.
    std::function<void(const std::string&)> log;
    /// Called once with the outcome before runFarm returns; after an interrupt or a cancel, before
    /// the workers are told to stop (under mpirun SIGKILL follows SIGTERM within about a second,
    /// so what the user must read goes out first). Not called when runFarm throws.
    std::function<void(const FarmOutcome&)> onEnd;
    /// Set: an interactive session (view_session.h) renders the views posted here, instead of
    /// job.frames() to sinks (which may then be empty), until cancel, a signal or a lost rank.
    ViewInbox* views = nullptr;
    /// The workers stay in their loops when the run ends (a viewer renders on with them); the
    /// caller sends kTagStop when it is done.
    bool keepWorkers = false;
    bool liveProgress = false;  ///< the master's live progress line (a terminal)
    bool quiet = false;         ///< no progress lines at all (a viewer shows its own)
    /// When the run started, for the wall time in the stats (the command's start, before loading).
    std::chrono::steady_clock::time_point wallStart = std::chrono::steady_clock::now();
};

enum class FarmEnd {
    Done,         ///< every frame is in the video
    Interrupted,  ///< SIGINT or SIGTERM: the video holds the frames done so far
    Cancelled,    ///< FarmOptions::cancel: the same, asked for by the caller
    WorkerLost,   ///< a worker died or stayed silent: the video holds the frames done so far
};

/// What a run did. Failures that are not a lost worker (a worker's error message, a sink that
/// cannot write) are thrown instead, after the workers are told to stop.
struct FarmOutcome {
    FarmEnd end = FarmEnd::Done;
    std::string error;       ///< WorkerLost: which rank stopped answering and what it was rendering
    int lostRank = -1;       ///< WorkerLost: that rank
    int signal = 0;          ///< Interrupted: SIGINT or SIGTERM
    std::string videoHolds;  ///< "the video out.mp4 holds frames 0–8 of 0–11"
    /// WorkerLost with workers left: they cannot be stopped politely; the caller ends every rank
    /// (MpiTransport::abort) once it has said why.
    bool abortRanks = false;
    /// Filled for every end (frames = frames in the video); written to job.statsPath when Done.
    RunStats stats;
};

/// Frames as the messages name them: "7" or "0–11".
std::string frameSpan(int first, int last);

/// Rank 0: renders job.frames() (those missing from the frames directory with job.resume) on
/// every rank of t and writes them to sinks. shared is the scene as shareScene delivered it;
/// its scene is moved into rank 0's renderer. Writes job.statsPath when the run is done.
FarmOutcome runFarm(Transport& t, const RenderJob& job, SharedScene& shared, FarmSinks sinks, const FarmOptions& opts);

/// Ranks 1…N−1: builds the renderer from the broadcast scene and job and serves rank 0 until
/// it says stop. Returns runWorker's status (0, 1 after a failure told to rank 0, 130 on a
/// signal, kMasterSilentExit when rank 0 was silent for masterTimeout seconds).
/// fpsOption is --fps as every rank parsed it (0: the scene's own).
int runFarmWorker(Transport& t, SharedScene& shared, double fpsOption, int threads, double masterTimeout);

}  // namespace rf::farm
