#pragma once
/// How a caller steers a run of the farm (FarmOptions) and what the run did (FarmOutcome), for
/// runFarm (run_farm.h) and its interactive session (view_session.h) alike.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "farm/output/run_stats.h"

namespace rf::farm {

struct FarmOutcome;
class ViewInbox;     // view_session.h
struct ViewPicture;  // view_session.h

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
    /// Called when a signal found the main thread held inside MPI and the watchdog ended the run
    /// (signal_deadline.h): after onEnd and the video's close, just before the process ends
    /// with no destructor run. Releases what must not outlive the process (the output locks).
    std::function<void()> onLastWords;
    /// Set: an interactive session (view_session.h) renders the views posted here, instead of
    /// job.frames() to sinks (which may then be empty), until cancel, a signal or a lost rank.
    ViewInbox* views = nullptr;
    /// The workers stay in their loops when the run ends (a viewer renders on with them); the
    /// caller sends kTagStop when it is done.
    bool keepWorkers = false;
    bool liveProgress = false;  ///< the master's live progress line (a terminal)
    bool quiet = false;         ///< no progress lines at all (a viewer shows its own)
    std::string progressLabel;  ///< before each progress line ("film 2 of 3, NAME" in a job of several)
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
    /// Workers given up on during the run, their work done by the others: the ranks left must
    /// not call MPI_Finalize, which would wait for them (MpiTransport::skipFinalize).
    int lostWorkers = 0;
    /// Filled for every end (frames = frames in the video); written to job.statsPath when Done.
    RunStats stats;
};

}  // namespace rf::farm
