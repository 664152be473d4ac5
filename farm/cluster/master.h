#pragma once
/// The master loop on rank 0: hands out work from a scheduler to the workers (and to rank 0's
/// own render engine when it renders too), gathers results into the frame assembler, passes
/// finished frames on in order, and watches every worker's heartbeat.
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "farm/cluster/chunk_collector.h"
#include "farm/cluster/chunk_workshop.h"
#include "farm/process/progress.h"
#include "farm/cluster/frame_assembler.h"
#include "farm/cluster/liveness.h"
#include "farm/cluster/render_engine.h"
#include "farm/output/run_stats.h"
#include "farm/cluster/scheduler.h"
#include "farm/cluster/transport.h"

namespace rf::farm {

struct MasterConfig {
    double workerTimeout = 10.0;  ///< seconds without a word from a busy worker before it counts as lost
    int credits = 2;              ///< items a worker holds at once: one rendering, one waiting
    /// Pixel mode: sub-tiles an item is split into on a rank (RenderEngine::subTilesOf); a rank
    /// that says it has T render threads then holds enough items for T ×
    /// RenderEngine::kSubTilesPerThread sub-tiles, twice over, if that is more than `credits`.
    /// 0: `credits` for every rank.
    int subTilesPerItem = 0;
    bool liveProgress = false;
    bool quiet = false;           ///< no progress lines (tests)
    int totalFrames = 0;          ///< frames in the output, for progress
    int keptFrames = 0;           ///< of those, kept from an earlier run: rendered from the start
    /// Pixels of one frame: a frame counts as rendered when its items' pixels are all back
    /// (0: each frame-mode item is a frame).
    int64_t framePixels = 0;
    std::string progressLabel;    ///< before each progress line (a film of a job of several)
    /// The caller's stop request (a viewer's cancel button): read like a signal, ends Interrupted.
    const std::atomic<bool>* cancel = nullptr;
    /// Called between scheduling steps (an interactive session: partial pictures, a newer
    /// view); true ends run() with RunEnd::Yielded, the work out left to the next retarget.
    std::function<bool()> between;
    /// Stamped on every item handed out; results of other epochs are dropped (newEpoch()).
    uint64_t epoch = 0;
    /// A worker lost (silent past workerTimeout: dead, stopped, cut off) has its work handed to
    /// the others and the run goes on, until no rendering rank is left or one frame was held by
    /// maxFrameFailures ranks when they were lost. false: the run ends WorkerLost at once.
    bool requeueLost = false;
    int maxFrameFailures = 3;
    /// Where notes about lost workers go (rank 0's log); nullptr: stderr.
    std::function<void(const std::string&)> log;
};

/// A worker given up on during a run (MasterConfig::requeueLost).
struct LostWorker {
    int rank = 0;
    std::string host;
    double atSeconds = 0.0;  ///< since the master started
    std::string doing;       ///< "while rendering frame 12 ..."
    std::string requeued;    ///< what went to the other ranks: "frames 12, 13; chunk 3 (frames 30–39)"
};

enum class RunEnd { Done, Interrupted, WorkerLost, Failed, Yielded };

struct MasterOutcome {
    RunEnd end = RunEnd::Done;
    std::string message;  ///< what went wrong, naming the rank and frame
    int lostRank = -1;    ///< WorkerLost: the rank
    int framesPassed = 0; ///< frames handed to `emit`, in order
    int lastFramePassed = -1;
    RayStats rays;
    std::vector<RankStats> perRank;  ///< index = rank
    std::chrono::steady_clock::time_point firstDispatch{};
    std::vector<LostWorker> lost;  ///< in the order they were lost
};

/// Tells every worker (ranks 1..size-1) to leave, skipping any that is gone, and waits up to
/// flushSeconds for the words to go out. Rank 0 calls it itself when it fails before its
/// master's loop starts, since a worker that hears nothing waits for work that never comes.
/// afterLoss: a worker was lost, so the others leave without MPI_Finalize (which would wait for
/// it: kStopAfterLossExit).
void tellWorkersToStop(Transport& t, double flushSeconds = 2.0, bool afterLoss = false);

/// Rank 0's set-up before its master's loop (the sinks, the frame plan, its own engine): an
/// exception that leaves the scope before dismiss() tells the workers to stop, so the error
/// line comes out and every rank leaves, instead of rank 0 waiting in MPI_Finalize for workers
/// that wait for work.
class StopWorkersOnThrow {
public:
    explicit StopWorkersOnThrow(Transport& t) : t_(t), uncaught_(std::uncaught_exceptions()) {}
    ~StopWorkersOnThrow();
    StopWorkersOnThrow(const StopWorkersOnThrow&) = delete;
    StopWorkersOnThrow& operator=(const StopWorkersOnThrow&) = delete;
    /// The master's loop takes over: it stops the workers however it ends.
    void dismiss() { armed_ = false; }

private:
    Transport& t_;
    int uncaught_;
    bool armed_ = true;
};

class Master {
public:
    /// local: rank 0's own engine, or nullptr when rank 0 only coordinates. emit receives every
    /// frame in output order (kept frames with onDisk set).
    Master(Transport& t, Scheduler& s, FrameAssembler& a, RenderEngine* local,
           std::function<void(ReadyFrame&)> emit, MasterConfig cfg);

    /// Called with each frame's pixels as soon as it is complete, before its turn in the output
    /// order (the PNG frames, so that nothing finished is lost to an interrupt).
    void onFrameComplete(std::function<void(int frame, const std::vector<uint8_t>& rgb)> f) { onComplete_ = std::move(f); }

    /// Called for each result accepted into the assembler, with the rank that rendered it.
    void onTile(std::function<void(int rank, const WorkItem&)> f) { onTile_ = std::move(f); }

    /// Chunked encoding: each chunk goes to a rank that assembles it from the items rendered
    /// for it and encodes it; the chunk's items are stamped with that rank (WorkItem::assembler)
    /// and their pixels never pass through rank 0. The scheduler hands out a marker for each
    /// chunk before its items. Frame mode (makeChunkFrameScheduler): whole frames, the marker
    /// naming the rank that will render most of them. Pixel mode (makeChunkTileScheduler):
    /// tiles, and the master picks the rank assembling fewest chunks. local (rank 0's own
    /// workshop over its engine, or nullptr) takes rank 0's part. orderFor makes a chunk's order (kept frames, pictures wanted);
    /// onFrame hears of each frame done (its PNG); emitChunk receives every encoded chunk in film
    /// order from collector. The frame assembler and emit are not used.
    struct ChunkHooks {
        ChunkCollector* collector = nullptr;
        ChunkWorkshop* local = nullptr;
        std::function<ChunkOrder(const WorkItem&)> orderFor;
        std::function<void(const ChunkFrame&)> onFrame;
        std::function<void(int chunk, std::string& bytes)> emitChunk;
    };
    void useChunks(ChunkHooks hooks) { chunks_ = std::move(hooks); }

    /// Runs until every frame is passed on, an interrupt, a lost worker or an error.
    MasterOutcome run();
    /// An interactive session's next pass: the work of epoch (stamped on every item handed
    /// out) from s into a; everything out before is forgotten, and its late results dropped.
    void retarget(Scheduler& s, FrameAssembler& a, uint64_t epoch);
    /// Between passes: keeps the workers told rank 0 lives and watches their heartbeats until
    /// wake() returns true (Yielded), a signal or the cancel flag (Interrupted), a worker's
    /// error (Failed) or a lost worker (WorkerLost).
    MasterOutcome idle(const std::function<bool()>& wake);
    /// After an interrupt: waits up to `seconds` for every busy worker to speak; returns the
    /// message for the first that does not (it probably died, which is why mpirun signalled us),
    /// or "" if all answered.
    std::string findSilentWorker(double seconds, int* rank = nullptr);
    /// Tells every worker to stop (once: later calls return at once).
    void stopWorkers();

private:
    struct WorkerState {
        int rank = 0;
        std::vector<WorkItem> outstanding;
        std::chrono::steady_clock::time_point lastHeard{};
        int reportedFrame = -1;
        bool building = false;  ///< its last heartbeat said it is still building its scene
        int threads = 0;        ///< render threads, as its heartbeat said (0: not yet)
        bool answeredAfterInterrupt = false;
        bool lost = false;       ///< given up on: its messages are ignored
        bool toldLost = false;   ///< it spoke again after that, and was told to leave
        std::vector<WorkItem> assembling;  ///< chunked encoding: the chunks it assembles and encodes
        /// Chunked encoding: items it rendered for another rank's chunk not yet encoded. Their
        /// pixels may not have reached that rank when this one is lost (a large message needs
        /// its sender alive), so they are rendered again then (requeueLost).
        std::vector<WorkItem> delivered;
    };
    void handle(const Message& m);
    /// A message from a rank (rank 0: its own workshop's).
    void dispatch(int rank, int tag, const std::string& bytes);
    void accept(int rank, const TileResult& r);
    /// Takes r's item off the rank's outstanding work and counts it; false (failure_ set) if the
    /// rank was not given it.
    bool tileReturned(int rank, const TileResult& r);
    /// Chunked encoding: the rank to assemble the chunk (the marker's, or the one assembling
    /// fewest), and the chunk's order sent there.
    void openAssembly(const WorkItem& chunk);
    void acceptChunkFrame(int rank, const ChunkFrame& f);
    void acceptChunkDone(int rank, const WorkItem& item, std::string bytes);
    /// Items the rank may hold (MasterConfig::credits, more for small items on many threads).
    int creditsOf(const WorkerState& w) const;
    /// Passes on what is ready, in order; true if anything was.
    bool passOn();
    /// rank 0's own results (engine or workshop); waits up to waitSeconds for one.
    bool gatherLocal(double waitSeconds);
    bool handOut();
    /// Reads every waiting message and local result; false if there was none.
    bool gather();
    /// The message for the first busy worker silent past the timeout, or "".
    std::string lostWorker(std::chrono::steady_clock::time_point now, int* rank) const;
    /// For progress: frames rendered and encoded, rendering ranks alive and busy.
    ProgressCounts progressCounts(std::chrono::steady_clock::time_point now) const;
    std::string describeBusy(const WorkerState& w) const;
    /// The frame the rank last said it renders (its heartbeat; rank 0's own engine's), or -1.
    int saidFrame(const WorkerState& w) const;
    std::string who(int rank) const;  // "rank 2 on node7"
    /// requeueLost: takes back the rank's work and hands it to the others. Returns "" while the
    /// run can go on, else why it cannot (no rendering rank left, a poison frame).
    std::string loseWorker(int rank, const std::string& why);
    /// A message from a rank given up on: said once, and the rank told to leave.
    void lateMessage(WorkerState& w, int tag);
    void note(const std::string& line) const;
    /// Sends to a worker; a worker that is gone shows up as silence, not as an error here.
    void sendTo(int rank, int tag, std::string bytes);
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
    std::unordered_map<int, std::vector<int>> frameFailures_;  ///< frame -> ranks lost holding it

    /// Interrupted (a signal or the cancel flag), with every worker's answer to it reset.
    bool interrupted();
    MasterOutcome finish(RunEnd end, std::string message);

    Transport& t_;
    Scheduler* sched_;
    FrameAssembler* asm_;
    RenderEngine* local_;
    std::function<void(ReadyFrame&)> emit_;
    std::function<void(int, const std::vector<uint8_t>&)> onComplete_;
    std::function<void(int, const WorkItem&)> onTile_;
    ChunkHooks chunks_;
    std::vector<int> assemblerOf_;  ///< pixel mode with chunks: by chunk, the rank assembling it
    int lastAssembler_ = 0;
    uint64_t epoch_ = 0;
    MasterConfig cfg_;
    std::vector<WorkerState> workers_;  ///< index = rank; rank 0 is the local engine if any
    MasterOutcome out_;
    bool dispatched_ = false;
    /// Frames rendered in this run (every pixel back), and the pixels back of frames not yet.
    int framesRendered_ = 0;
    std::unordered_map<int, int64_t> pixelsBack_;
    bool stopped_ = false;  ///< stopWorkers has sent its word
    PauseDetector pause_;
    std::chrono::steady_clock::time_point lastBeat_{};
    void keepAlive(std::chrono::steady_clock::time_point now);
    std::string failure_;
};

}  // namespace rf::farm
