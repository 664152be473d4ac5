#include "farm/cluster/master.h"

#include <algorithm>
#include <cstdio>
#include <thread>
#include <utility>

#include "farm/process/interrupt.h"
#include "farm/process/progress.h"

namespace rf::farm {

using Clock = std::chrono::steady_clock;

Master::Master(Transport& t, Scheduler& s, FrameAssembler& a, RenderEngine* local, std::function<void(ReadyFrame&)> emit,
               MasterConfig cfg)
    : t_(t), sched_(&s), asm_(&a), local_(local), emit_(std::move(emit)), cfg_(cfg) {
    epoch_ = cfg_.epoch;
    workers_.resize(size_t(t.size()));
    out_.perRank.resize(size_t(t.size()));
    const auto now = Clock::now();
    for (int r = 0; r < t.size(); ++r) {
        workers_[size_t(r)].rank = r;
        workers_[size_t(r)].lastHeard = now;
        out_.perRank[size_t(r)].rank = r;
    }
}

std::string Master::who(int rank) const {
    const std::string host = t_.host(rank);
    return "rank " + std::to_string(rank) + (host.empty() ? "" : " on " + host);
}

int Master::saidFrame(const WorkerState& w) const { return w.rank == 0 && local_ ? local_->currentFrame() : w.reportedFrame; }

std::string Master::describeBusy(const WorkerState& w) const {
    if (w.building) return "while building its scene";
    if (w.outstanding.empty() && !w.assembling.empty()) return "while assembling chunk " + std::to_string(w.assembling.front().chunk);
    if (w.outstanding.empty()) return "while idle";
    // Items run in the order given: the first is the one being rendered, the rest wait (unless
    // the rank said it renders another of them: the first may be done, its note not yet sent).
    std::vector<int> frames;
    const int said = saidFrame(w);
    if (std::any_of(w.outstanding.begin(), w.outstanding.end(), [&](const WorkItem& i) { return i.frame == said; }))
        frames.push_back(said);
    for (const WorkItem& i : w.outstanding)
        if (std::find(frames.begin(), frames.end(), i.frame) == frames.end()) frames.push_back(i.frame);
    std::string s = "while rendering frame " + std::to_string(frames[0]);
    if (chunks_.collector) {  // and the chunk it is for
        const ChunkPlan& plan = chunks_.collector->plan();
        const int c = plan.chunkOf(frames[0]);
        s += " of chunk " + std::to_string(c) + " (frames " + std::to_string(plan.firstFrame(c)) + "–" +
             std::to_string(plan.lastFrame(c)) + ")";
    }
    if (frames.size() > 1) {
        s += " (queued: frame";
        for (size_t i = 1; i < frames.size(); ++i) {
            s += i > 1 ? ", " : " ";
            s += std::to_string(frames[i]);
        }
        s += ")";
    }
    return s;
}

void Master::accept(int rank, const TileResult& r) {
    if (r.item.epoch != epoch_) return;  // work of a view since replaced
    if (!tileReturned(rank, r)) return;
    if (asm_->add(r) && onComplete_) onComplete_(r.item.frame, *asm_->completed(r.item.frame));
}

bool Master::tileReturned(int rank, const TileResult& r) {
    WorkerState& w = workers_[size_t(rank)];
    auto it = std::find_if(w.outstanding.begin(), w.outstanding.end(), [&](const WorkItem& i) {
        return i.frame == r.item.frame && i.rect.x0 == r.item.rect.x0 && i.rect.y0 == r.item.rect.y0 &&
               i.rect.x1 == r.item.rect.x1 && i.rect.y1 == r.item.rect.y1;
    });
    if (it == w.outstanding.end()) {
        failure_ = "rank " + std::to_string(rank) + " returned frame " + std::to_string(r.item.frame) +
                   " work it was not given";
        return false;
    }
    w.outstanding.erase(it);
    if (cfg_.framePixels <= 0) {
        if (sched_->mode() == Mode::Frame) ++framesRendered_;
    } else if ((pixelsBack_[r.item.frame] += r.item.rect.pixels()) >= cfg_.framePixels) {
        pixelsBack_.erase(r.item.frame);
        ++framesRendered_;
    }
    if (onTile_) onTile_(rank, r.item);
    out_.rays += r.rays;
    RankStats& st = out_.perRank[size_t(rank)];
    st.busySeconds += r.busySeconds;
    if (sched_->mode() == Mode::Frame) ++st.frames;
    else ++st.tiles;
    return true;
}

void Master::openAssembly(const WorkItem& chunk) {
    // The rank the scheduler named (frame mode: the one that will render the chunk's frames),
    // else the rendering rank assembling fewest chunks, taking ranks in turn on a tie.
    const int n = int(workers_.size());
    const bool named = chunk.assembler >= (local_ ? 0 : 1) && chunk.assembler < n;
    int best = named ? chunk.assembler : -1;
    for (int step = 1; step <= n && !named; ++step) {
        const int r = (lastAssembler_ + step) % n;
        if ((r == 0 && !local_) || workers_[size_t(r)].lost) continue;
        if (best < 0 || workers_[size_t(r)].assembling.size() < workers_[size_t(best)].assembling.size()) best = r;
    }
    lastAssembler_ = best;
    if (assemblerOf_.size() <= size_t(chunk.chunk)) assemblerOf_.resize(size_t(chunk.chunk) + 1, -1);
    assemblerOf_[size_t(chunk.chunk)] = best;
    WorkerState& w = workers_[size_t(best)];
    w.assembling.push_back(chunk);
    ChunkOrder order = chunks_.orderFor(chunk);
    if (best == 0) chunks_.local->submitAssembly(std::move(order));
    else sendTo(best, kTagChunkAssemble, encodeChunkOrder(order));
}

void Master::handle(const Message& m) {
    if (m.source <= 0 || m.source >= int(workers_.size())) return;
    WorkerState& w = workers_[size_t(m.source)];
    if (w.lost) return lateMessage(w, m.tag);
    w.lastHeard = Clock::now();
    w.answeredAfterInterrupt = true;
    dispatch(m.source, m.tag, m.bytes);
}

void Master::dispatch(int rank, int tag, const std::string& bytes) {
    WorkerState& w = workers_[size_t(rank)];
    switch (tag) {
    case kTagResult:
        accept(rank, decodeTileResult(bytes));
        break;
    case kTagTileDone: {
        const TileResult r = decodeTileDone(bytes);
        if (r.item.epoch == epoch_ && tileReturned(rank, r) && cfg_.requeueLost && r.item.assembler >= 0 && r.item.assembler != rank)
            w.delivered.push_back(r.item);
        break;
    }
    case kTagTile:  // a tile of a chunk rank 0 assembles itself
        if (!chunks_.local) throw std::runtime_error(who(rank) + " sent a tile to rank 0, which assembles no chunk");
        chunks_.local->addTile(decodeTileResult(bytes));
        break;
    case kTagChunkFrame:
        acceptChunkFrame(rank, decodeChunkFrame(bytes));
        break;
    case kTagChunkDone: {
        std::string chunk;
        const WorkItem item = decodeChunkDone(bytes, chunk);
        acceptChunkDone(rank, item, std::move(chunk));
        break;
    }
    case kTagHeartbeat: {
        const Heartbeat h = decodeHeartbeat(bytes);
        w.reportedFrame = h.currentFrame;
        w.building = h.building != 0;
        if (h.threads > 0) w.threads = h.threads;
        break;
    }
    case kTagError:
        failure_ = who(rank) + ": " + bytes;
        break;
    default:
        break;
    }
}

void Master::acceptChunkFrame(int rank, const ChunkFrame& f) {
    if (f.item.epoch != epoch_) return;
    std::vector<WorkItem>& chunks = workers_[size_t(rank)].assembling;
    const auto it = std::find_if(chunks.begin(), chunks.end(), [&](const WorkItem& i) { return i.chunk == f.item.chunk; });
    if (!chunks_.collector || it == chunks.end() || f.frame < it->frame || f.frame >= it->frame + it->frames) {
        failure_ = "rank " + std::to_string(rank) + " returned frame " + std::to_string(f.frame) + " of chunk " +
                   std::to_string(f.item.chunk) + ", work it was not given";
        return;
    }
    // The frame's items were counted as their notes came (kTagTileDone).
    if (chunks_.onFrame) chunks_.onFrame(f);
}

void Master::acceptChunkDone(int rank, const WorkItem& item, std::string bytes) {
    if (item.epoch != epoch_) return;
    std::vector<WorkItem>& chunks = workers_[size_t(rank)].assembling;
    const auto it = std::find_if(chunks.begin(), chunks.end(), [&](const WorkItem& i) { return i.chunk == item.chunk; });
    if (!chunks_.collector || it == chunks.end()) {
        failure_ = "rank " + std::to_string(rank) + " returned chunk " + std::to_string(item.chunk) + ", work it was not given";
        return;
    }
    chunks.erase(it);
    chunks_.collector->add(item.chunk, std::move(bytes));
    // Its frames are in: nothing rendered for it need be rendered again.
    const ChunkPlan& plan = chunks_.collector->plan();
    for (WorkerState& x : workers_)
        x.delivered.erase(std::remove_if(x.delivered.begin(), x.delivered.end(),
                                         [&](const WorkItem& i) { return plan.chunkOf(i.frame) == item.chunk; }),
                          x.delivered.end());
}

int Master::creditsOf(const WorkerState& w) const {
    const int threads = w.rank == 0 && local_ ? local_->threads() : w.threads;
    if (cfg_.subTilesPerItem <= 0 || threads <= 0) return cfg_.credits;
    const int perBatch = threads * RenderEngine::kSubTilesPerThread;
    return std::max(cfg_.credits, 2 * ((perBatch + cfg_.subTilesPerItem - 1) / cfg_.subTilesPerItem));
}

bool Master::handOut() {
    bool any = false;
    // Round-robin by rank, one item per pass, so credits fill evenly.
    for (bool more = true; more;) {
        more = false;
        for (WorkerState& w : workers_) {
            if ((w.rank == 0 && !local_) || w.lost) continue;
            if (int(w.outstanding.size()) >= creditsOf(w)) continue;
            std::optional<WorkItem> item = sched_->take(w.rank);
            for (; item && chunks_.collector && item->chunk >= 0; item = sched_->take(w.rank)) {
                item->epoch = epoch_;
                openAssembly(*item);  // a chunk's marker: its frames or tiles follow
                any = true;
            }
            if (!item) return any;
            item->epoch = epoch_;
            if (chunks_.collector) item->assembler = assemblerOf_.at(size_t(chunks_.collector->plan().chunkOf(item->frame)));
            if (!dispatched_) {
                dispatched_ = true;
                out_.firstDispatch = Clock::now();
            }
            w.outstanding.push_back(*item);
            if (w.rank == 0) {
                local_->submit(*item);  // with a workshop, its poll routes the result
            } else {
                sendTo(w.rank, kTagWork, encodeWorkItem(*item));
            }
            any = more = true;
        }
    }
    return any;
}

/// Tells every worker rank 0 still runs, and notices when rank 0 itself was stopped: the
/// silence it then sees is its own, so every worker's timeout starts again.
void Master::keepAlive(Clock::time_point now) {
    if (pause_.resumed(now))
        for (WorkerState& w : workers_) w.lastHeard = now;
    // A worker leaves when rank 0 is silent for --timeout: several beats fit in it.
    if (std::chrono::duration<double>(now - lastBeat_).count() < std::min(kMasterBeatSeconds, cfg_.workerTimeout / 4)) return;
    lastBeat_ = now;
    for (int r = 1; r < t_.size(); ++r)
        if (!workers_[size_t(r)].lost) sendTo(r, kTagAlive, "");
}

bool Master::gather() {
    bool progressed = false;
    try {
        Message m;
        while (t_.poll(m)) {
            handle(m);
            progressed = true;
        }
        if (local_) progressed |= gatherLocal(0.0);
    } catch (const std::exception& e) {
        if (failure_.empty()) failure_ = e.what();
    }
    return progressed;
}

bool Master::gatherLocal(double waitSeconds) {
    bool any = false;
    if (chunks_.local) {
        for (ChunkWorkshop::Outgoing& o : chunks_.local->poll(waitSeconds)) {
            if (o.dest == 0) dispatch(0, o.tag, o.bytes);
            else sendTo(o.dest, o.tag, std::move(o.bytes));  // a tile for the rank assembling its frame
            any = true;
        }
        if (const std::string err = chunks_.local->error(); !err.empty()) failure_ = "rank 0: " + err;
        return any;
    }
    for (auto r = local_->takeResult(waitSeconds); r; r = local_->takeResult()) {
        accept(0, *r);
        any = true;
    }
    if (const std::string err = local_->error(); !err.empty()) failure_ = "rank 0: " + err;
    return any;
}

bool Master::passOn() {
    bool any = false;
    if (chunks_.collector) {
        int chunk = 0;
        std::string bytes;
        while (chunks_.collector->popReady(chunk, bytes)) {
            chunks_.emitChunk(chunk, bytes);
            sched_->frameReleased();
            out_.framesPassed += chunks_.collector->plan().framesIn(chunk);
            out_.lastFramePassed = chunks_.collector->plan().lastFrame(chunk);
            any = true;
        }
        return any;
    }
    ReadyFrame rf;
    while (asm_->popReady(rf)) {
        const bool rendered = !rf.onDisk;
        emit_(rf);
        if (rendered) sched_->frameReleased();
        ++out_.framesPassed;
        out_.lastFramePassed = rf.frame;
        any = true;
    }
    return any;
}

std::string Master::lostWorker(Clock::time_point now, int* rank) const {
    for (const WorkerState& w : workers_) {
        if (w.rank == 0 || w.lost) continue;
        const double silent = std::chrono::duration<double>(now - w.lastHeard).count();
        if (silent > cfg_.workerTimeout) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.1f", silent);
            *rank = w.rank;
            return who(w.rank) + " stopped answering (silent for " + buf + " s) " + describeBusy(w);
        }
    }
    return "";
}

ProgressCounts Master::progressCounts(Clock::time_point now) const {
    ProgressCounts c;
    c.rendered = std::min(cfg_.totalFrames, cfg_.keptFrames + framesRendered_);
    c.encoded = out_.framesPassed;
    c.rendered = std::max(c.rendered, c.encoded);  // a frame encoded was rendered
    for (const WorkerState& w : workers_) {
        if ((w.rank == 0 && !local_) || w.lost) continue;  // rank 0 only schedules and encodes
        // Alive: rank 0's own engine, or a rank heard from within the worker timeout.
        const bool alive = w.rank == 0 || std::chrono::duration<double>(now - w.lastHeard).count() <= cfg_.workerTimeout;
        if (!alive) continue;
        ++c.alive;
        if (!w.outstanding.empty()) ++c.busy;
    }
    return c;
}

bool Master::interrupted() {
    if (!interruptSignal() && !(cfg_.cancel && cfg_.cancel->load())) return false;
    for (WorkerState& w : workers_) w.answeredAfterInterrupt = false;
    if (local_) local_->cancelQueued();
    if (chunks_.local) chunks_.local->cancel();
    return true;
}

MasterOutcome Master::finish(RunEnd end, std::string message) {
    out_.end = end;
    out_.message = std::move(message);
    return out_;
}

MasterOutcome Master::run() {
    Progress progress(cfg_.totalFrames, cfg_.liveProgress, stderr, cfg_.progressLabel);
    auto finish = [&](RunEnd end, std::string msg) {
        if (!cfg_.quiet) progress.finish();
        return this->finish(end, std::move(msg));
    };
    for (;;) {
        if (interrupted()) return finish(RunEnd::Interrupted, "");
        if (cfg_.between && cfg_.between()) return finish(RunEnd::Yielded, "");
        keepAlive(Clock::now());
        bool progressed = handOut();
        progressed |= gather();
        if (!failure_.empty()) return finish(RunEnd::Failed, failure_);

        progressed |= passOn();
        if (!failure_.empty()) return finish(RunEnd::Failed, failure_);
        // Chunks: an item's note to rank 0 comes from its renderer and the chunk from its
        // assembler, in either order, so the last notes may follow the last chunk.
        if (sched_->exhausted() && (chunks_.collector ? chunks_.collector->finished() : asm_->finished()) &&
            std::all_of(workers_.begin(), workers_.end(), [](const WorkerState& w) { return w.outstanding.empty(); }))
            return finish(RunEnd::Done, "");

        // Heartbeats are read above before this check, so time spent blocked in emit (a full
        // encoder queue) never counts against a worker.
        const auto now = Clock::now();
        keepAlive(now);  // emit may have blocked, or this process been stopped, since the top
        if (std::string lost = lostWorker(now, &out_.lostRank); !lost.empty()) {
            if (!cfg_.requeueLost) return finish(RunEnd::WorkerLost, std::move(lost));
            if (std::string end = loseWorker(out_.lostRank, lost); !end.empty()) return finish(RunEnd::WorkerLost, std::move(end));
            out_.lostRank = -1;
            continue;  // its work goes out again at once
        }
        if (!cfg_.quiet) progress.update(progressCounts(now));
        if (!progressed) {
            if (local_) {
                // Alone, with no ranks to hear from and no viewer waiting between frames, the
                // loop sleeps until a frame is done (a result wakes it at once). With workers it
                // looks every 2 ms: each holds several items (credits), so a result read that
                // late never leaves a worker without work, while waking every 0.5 ms took the
                // render thread's core from it (2CylinderEngine, pixel mode, 2 ranks: 33.7 ->
                // 36.4 fps with the workers' 2 ms and 8 credits). A viewer waits 0.5 ms.
                const double wait = cfg_.between ? 0.0005 : t_.size() == 1 ? 0.02 : 0.002;
                try {
                    gatherLocal(wait);
                } catch (const std::exception& e) {
                    if (failure_.empty()) failure_ = e.what();
                }
            } else {
                std::this_thread::sleep_for(std::chrono::microseconds(300));
            }
        }
    }
}

void Master::retarget(Scheduler& s, FrameAssembler& a, uint64_t epoch) {
    sched_ = &s;
    asm_ = &a;
    epoch_ = epoch;
    // Workers drop the old epoch's work when its ViewSpec reaches them, before the new items.
    for (WorkerState& w : workers_) w.outstanding.clear();
}

MasterOutcome Master::idle(const std::function<bool()>& wake) {
    for (;;) {
        if (interrupted()) return finish(RunEnd::Interrupted, "");
        if (wake()) return finish(RunEnd::Yielded, "");
        const auto now = Clock::now();
        keepAlive(now);
        gather();
        if (!failure_.empty()) return finish(RunEnd::Failed, failure_);
        if (std::string lost = lostWorker(now, &out_.lostRank); !lost.empty()) return finish(RunEnd::WorkerLost, std::move(lost));
        std::this_thread::sleep_for(std::chrono::microseconds(300));
    }
}

std::string Master::findSilentWorker(double seconds, int* rank) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
        Message m;
        try {
            while (t_.poll(m))
                if (m.source > 0 && m.source < int(workers_.size())) workers_[size_t(m.source)].answeredAfterInterrupt = true;
        } catch (const std::exception&) {
            // A failing receive says as much as silence.
        }
        const WorkerState* silent = nullptr;
        for (const WorkerState& w : workers_)
            if (w.rank > 0 && !w.lost && !w.answeredAfterInterrupt) {
                silent = &w;
                break;
            }
        if (!silent) return "";
        if (Clock::now() > end) {
            if (rank) *rank = silent->rank;
            return who(silent->rank) + " stopped answering " + describeBusy(*silent) +
                   " (it probably died: mpirun stops the whole job when a rank does, unless started with --enable-recovery)";
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

void Master::note(const std::string& line) const {
    if (cfg_.log) cfg_.log(line);
    else std::fprintf(stderr, "rayfarm: %s\n", line.c_str());
}

void Master::sendTo(int rank, int tag, std::string bytes) {
    try {
        t_.send(rank, tag, std::move(bytes));
    } catch (const TransportError&) {
        // A worker that is gone shows up as its silence (lostWorker).
    }
}

void Master::lateMessage(WorkerState& w, int tag) {
    if (w.toldLost) return;
    w.toldLost = true;
    note("note: " + who(w.rank) + " answered again (" + (tag == kTagHeartbeat ? std::string("a heartbeat") : "message tag " + std::to_string(tag)) +
         ") after it was given up on; what it sends is ignored, its work is done elsewhere, and it is told to leave");
    sendTo(w.rank, kTagStop, kStopAfterLoss);
}

namespace {

/// "frames 3, 4, 9" from items (each frame once, in the order given).
std::string framesOf(const std::vector<WorkItem>& items) {
    std::vector<int> frames;
    for (const WorkItem& i : items)
        if (std::find(frames.begin(), frames.end(), i.frame) == frames.end()) frames.push_back(i.frame);
    std::string s = frames.size() == 1 ? "frame" : "frames";
    for (size_t i = 0; i < frames.size(); ++i) s += (i ? ", " : " ") + std::to_string(frames[i]);
    return s;
}

}  // namespace

std::string Master::loseWorker(int rank, const std::string& why) {
    WorkerState& w = workers_[size_t(rank)];
    LostWorker lw;
    lw.rank = rank;
    lw.host = t_.host(rank);
    lw.atSeconds = std::chrono::duration<double>(Clock::now() - started_).count();
    lw.doing = describeBusy(w);
    // The frame it was on when it went: a frame that takes every rank down with it is given up on.
    int culprit = -1;
    const int said = saidFrame(w);
    for (const WorkItem& i : w.outstanding)
        if (i.frame == said) culprit = said;
    if (culprit < 0 && !w.outstanding.empty()) culprit = w.outstanding.front().frame;
    // Chunks it assembled open again on other ranks, every frame of them; the items it held of
    // other chunks (or of no chunk) go out again as they were.
    std::vector<int> reopened;
    std::string chunksText;
    for (const WorkItem& c : w.assembling) {
        sched_->reopenChunk(c.chunk);
        reopened.push_back(c.chunk);
        chunksText += (chunksText.empty() ? "chunk " : ", chunk ") + std::to_string(c.chunk) + " (frames " + std::to_string(c.frame) + "–" +
                      std::to_string(c.frame + c.frames - 1) + ")";
    }
    std::vector<WorkItem> requeued;
    std::vector<WorkItem> items = w.outstanding;
    items.insert(items.end(), w.delivered.begin(), w.delivered.end());
    for (const WorkItem& i : items) {
        if (chunks_.collector &&
            std::find(reopened.begin(), reopened.end(), chunks_.collector->plan().chunkOf(i.frame)) != reopened.end())
            continue;
        sched_->requeue(i);
        requeued.push_back(i);
    }
    lw.requeued = requeued.empty() ? "" : framesOf(requeued);
    if (sched_->mode() == Mode::Pixel && !requeued.empty())
        lw.requeued += " (" + std::to_string(requeued.size()) + (requeued.size() == 1 ? " tile)" : " tiles)");
    if (!chunksText.empty()) lw.requeued += (lw.requeued.empty() ? "" : "; ") + chunksText;
    if (lw.requeued.empty()) lw.requeued = "nothing";
    w.outstanding.clear();
    w.assembling.clear();
    w.delivered.clear();
    w.lost = true;
    out_.lost.push_back(lw);
    if (culprit >= 0) {
        std::vector<int>& ranks = frameFailures_[culprit];
        ranks.push_back(rank);
        if (int(ranks.size()) >= std::max(1, cfg_.maxFrameFailures)) {
            std::string list;
            for (size_t i = 0; i < ranks.size(); ++i) list += (i ? ", " : "") + std::to_string(ranks[i]);
            return why + "; frame " + std::to_string(culprit) + " was being rendered by each of the " + std::to_string(ranks.size()) +
                   " ranks lost so far holding it (ranks " + list + "): a frame that takes down every worker it reaches, "
                   "given up on (--max-frame-failures " + std::to_string(cfg_.maxFrameFailures) + ")";
        }
    }
    const bool renderersLeft =
        local_ || std::any_of(workers_.begin() + 1, workers_.end(), [](const WorkerState& x) { return !x.lost; });
    if (!renderersLeft) return why + "; no worker is left to render";
    int alive = 0;
    for (const WorkerState& x : workers_)
        if (!x.lost && (x.rank > 0 || local_)) ++alive;
    note("warning: " + why + "; its work goes to the " + std::to_string(alive) + " rendering rank" + (alive == 1 ? "" : "s") +
         " left: " + lw.requeued);
    return "";
}

void tellWorkersToStop(Transport& t, double flushSeconds, bool afterLoss) {
    for (int r = 1; r < t.size(); ++r) {
        try {
            t.send(r, kTagStop, afterLoss ? kStopAfterLoss : "");
        } catch (const TransportError&) {
            // That worker is gone; the others still need the word.
        }
    }
    t.flush(flushSeconds);
}

StopWorkersOnThrow::~StopWorkersOnThrow() {
    if (!armed_ || std::uncaught_exceptions() <= uncaught_) return;
    try {
        tellWorkersToStop(t_);
    } catch (...) {
        // Unwinding already: the error that brought us here is the one to tell.
    }
}

void Master::stopWorkers() {
    if (std::exchange(stopped_, true)) return;  // a second word would wait for ranks that left
    // A lost rank's sends never complete: the others' words go out well within a second.
    tellWorkersToStop(t_, out_.lost.empty() ? 2.0 : 1.0, !out_.lost.empty());
}

}  // namespace rf::farm
