#include "farm/cluster/view_session.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <set>
#include <stdexcept>

#include "farm/cluster/farm_options.h"
#include "farm/cluster/frame_assembler.h"
#include "farm/process/interrupt.h"
#include "farm/cluster/master.h"
#include "farm/cluster/render_engine.h"
#include "farm/cluster/render_job.h"
#include "farm/cluster/scene_broadcast.h"
#include "farm/cluster/scheduler.h"
#include "anim/timeline.h"

namespace rf::farm {

namespace {

using Clock = std::chrono::steady_clock;

/// A slow pass shows the tiles done so far this often.
constexpr auto kPartialEvery = std::chrono::milliseconds(150);
/// Items each rank holds: one rendering and the next ones waiting, as in render's pixel mode.
constexpr int kCredits = 4;

/// Work items of a pass: with several renderers, small enough that each holds a few of even a
/// quarter-size moving frame; alone, larger (fewer hand-overs), still several per pass so a
/// slow pass shows progress.
int passTile(int renderers) { return renderers > 1 ? 64 : 128; }

/// Rank 0's side of one session: the views from the inbox, pass by pass, through one Master.
class ViewSession {
public:
    ViewSession(Transport& t, const RenderJob& job, const FarmOptions& opts)
        : t_(t), job_(job), opts_(opts), rank0Renders_(t.size() <= 2) {}

    FarmOutcome run(SharedScene& shared);

private:
    MasterConfig masterConfig();
    void startPass(Master& master);
    /// Between the master's steps: true when a newer view waits; meanwhile partial pictures.
    bool between();
    void publish(const std::vector<uint8_t>& rgb, bool complete);
    FarmOutcome conclude(Master& master, const MasterOutcome& o);

    Transport& t_;
    const RenderJob& job_;
    const FarmOptions& opts_;
    bool rank0Renders_;  ///< as in render: with three ranks or more, rank 0 only coordinates
    PixelLayout layout_;
    std::unique_ptr<RenderEngine> local_;
    std::unique_ptr<Scheduler> sched_;
    std::unique_ptr<FrameAssembler> asm_;
    ViewOrder view_;
    size_t pass_ = 0;
    std::vector<ViewTile> tiles_;
    Clock::time_point passStart_, lastPartial_;
};

MasterConfig ViewSession::masterConfig() {
    MasterConfig cfg;
    cfg.workerTimeout = job_.workerTimeout;
    cfg.credits = kCredits;
    cfg.quiet = true;
    cfg.cancel = opts_.cancel;
    cfg.between = [this] { return between(); };
    return cfg;
}

FarmOutcome ViewSession::run(SharedScene& shared) {
    layout_ = PixelLayout{shared.scene.transparentBackground ? 4 : 3, false};
    if (rank0Renders_) {
        anim::Timeline timeline = anim::Timeline::fromScene(shared, job_.fpsOption);
        local_ = std::make_unique<RenderEngine>(std::move(shared.scene), timeline, job_.settings,
                                                std::max(1, opts_.threads), false, nullptr, shared.bounceSlot);
    }
    // Nothing to render until the first view: an empty scheduler and assembler.
    sched_ = makePixelScheduler(anim::FrameRanges{}, 1, 1, 1, 1);
    asm_ = std::make_unique<FrameAssembler>(1, 1, anim::FrameRanges{}, anim::FrameRanges{}, layout_);
    Master master(t_, *sched_, *asm_, local_.get(), [this](ReadyFrame& rf) { publish(rf.rgb, true); }, masterConfig());
    master.onTile([this](int rank, const WorkItem& w) { tiles_.push_back({w.rect, rank}); });
    for (;;) {
        MasterOutcome o = master.idle([this] { return opts_.views->pending(); });
        if (o.end != RunEnd::Yielded) return conclude(master, o);
        view_ = *opts_.views->take();
        for (pass_ = 0; pass_ < view_.passes.size(); ++pass_) {
            startPass(master);
            o = master.run();
            if (o.end == RunEnd::Yielded) break;  // a newer view: its first pass cancels this one
            if (o.end != RunEnd::Done) return conclude(master, o);
        }
    }
}

void ViewSession::startPass(Master& master) {
    const ViewPass& p = view_.passes[pass_];
    ViewSpec spec;
    spec.epoch = newEpoch();  // never one of an earlier run's
    spec.frame = view_.frame;
    spec.followTimeline = view_.followTimeline ? 1 : 0;
    spec.spp = p.spp;
    spec.width = p.width;
    spec.height = p.height;
    spec.camera = view_.camera;
    // Before the pass's items: messages from rank 0 arrive in order, so every rank drops the
    // older work before it sees the new.
    const std::string bytes = encodeViewSpec(spec);
    for (int r = 1; r < t_.size(); ++r) {
        try {
            t_.send(r, kTagView, bytes);
        } catch (const TransportError&) {
            // A lost rank shows up as silence.
        }
    }
    if (local_) local_->setView(spec);
    const int renderers = rank0Renders_ ? t_.size() : t_.size() - 1;
    auto sched = makePixelScheduler(anim::FrameRanges{view_.frame}, p.width, p.height, passTile(renderers), 1);
    auto assembler = std::make_unique<FrameAssembler>(p.width, p.height, anim::FrameRanges{view_.frame}, anim::FrameRanges{}, layout_);
    master.retarget(*sched, *assembler, spec.epoch);
    sched_ = std::move(sched);
    asm_ = std::move(assembler);
    tiles_.clear();
    passStart_ = lastPartial_ = Clock::now();
}

bool ViewSession::between() {
    if (opts_.views->pending()) return true;
    const auto now = Clock::now();
    if (opts_.onFrame && !tiles_.empty() && now - lastPartial_ > kPartialEvery) {
        lastPartial_ = now;
        if (const std::vector<uint8_t>* px = asm_->pixels(view_.frame)) publish(*px, false);
    }
    return false;
}

void ViewSession::publish(const std::vector<uint8_t>& rgb, bool complete) {
    if (!opts_.onFrame) return;
    ViewPicture pic;
    pic.id = view_.id;
    pic.pass = int(pass_);
    pic.passes = int(view_.passes.size());
    pic.size = view_.passes[pass_];
    pic.complete = complete;
    pic.ms = std::chrono::duration<double, std::milli>(Clock::now() - passStart_).count();
    pic.tiles = &tiles_;
    FarmProgress p;
    p.frame = view_.frame;
    p.framesDone = complete ? 1 : 0;
    p.framesTotal = 1;
    p.rgb = &rgb;
    p.view = &pic;
    opts_.onFrame(p);
}

FarmOutcome ViewSession::conclude(Master& master, const MasterOutcome& o) {
    FarmOutcome out;
    out.stats.ranks = t_.size();
    out.stats.threadsPerRank = opts_.threads;
    // After mpirun's SIGTERM: a rank that does not answer it is most likely why it came.
    std::string silent;
    int silentRank = -1;
    if (o.end == RunEnd::Interrupted && interruptSignal() && t_.size() > 1) silent = master.findSilentWorker(0.5, &silentRank);
    if (o.end == RunEnd::WorkerLost || !silent.empty()) {
        out.end = FarmEnd::WorkerLost;
        out.error = silent.empty() ? o.message : silent;
        out.lostRank = silent.empty() ? o.lostRank : silentRank;
        out.abortRanks = t_.size() > 1;
        if (opts_.onEnd) opts_.onEnd(out);
        return out;
    }
    if (o.end == RunEnd::Failed) {
        if (!opts_.keepWorkers) master.stopWorkers();
        throw std::runtime_error(o.message);
    }
    out.signal = interruptSignal();
    out.end = out.signal ? FarmEnd::Interrupted : FarmEnd::Cancelled;
    if (opts_.onEnd) opts_.onEnd(out);  // before the workers hear: after a signal SIGKILL is near
    if (!opts_.keepWorkers) master.stopWorkers();
    return out;
}

}  // namespace

FarmOutcome runViewSession(Transport& t, const RenderJob& job, SharedScene& shared, const FarmOptions& opts) {
    if (!opts.views) throw std::invalid_argument("runViewSession: no view inbox");
    ViewSession session(t, job, opts);
    return session.run(shared);
}

}  // namespace rf::farm
