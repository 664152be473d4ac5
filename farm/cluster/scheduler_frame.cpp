#include <algorithm>

#include "farm/cluster/scheduler.h"

namespace rf::farm {

namespace {

class FrameScheduler : public Scheduler {
public:
    FrameScheduler(anim::FrameRanges frames, int width, int height, int window)
        : Scheduler(std::move(frames), window), full_{0, 0, width, height} {}

    std::optional<WorkItem> next() override {
        const std::optional<int> f = openNextFrame();
        if (!f) return std::nullopt;
        return WorkItem{*f, full_};
    }
    int itemsPerFrame() const override { return 1; }
    Mode mode() const override { return Mode::Frame; }

private:
    TileRect full_;
};

/// Frame mode with chunked encoding, a chunk's frames handed out one at a time: see
/// makeChunkFrameScheduler. The scheduler's "frames" are the chunks' numbers, so the window
/// counts chunks open.
class ChunkFrameScheduler : public Scheduler {
public:
    ChunkFrameScheduler(const ChunkPlan& plan, anim::FrameRanges kept, int width, int height, int window)
        : Scheduler(anim::FrameRanges::span(0, plan.count() - 1), window), plan_(plan), kept_(std::move(kept)),
          full_{0, 0, width, height} {}

    /// As asked by a rank that owns no chunk: the chunks it opens belong to whichever rank the
    /// master picks, and their frames go to next()'s callers first.
    std::optional<WorkItem> next() override { return nextFor(-1); }

    std::optional<WorkItem> nextFor(int rank) override {
        for (size_t i = 0; i < open_.size();)
            if (trim(open_[i])) ++i;
            else open_.erase(open_.begin() + long(i));  // every frame of it handed out
        // Its own chunk's next frame, the oldest chunk first.
        for (OpenChunk& c : open_)
            if (c.owner == rank) return frame(c.next++);
        // A chunk of its own: one whose rank was lost first (it holds the film up), then the
        // next; the marker now, its first frame when the master asks again.
        std::optional<int> n;
        if (!reopen_.empty()) {
            n = reopen_.front();
            reopen_.pop_front();
        } else {
            n = openNextFrame();
        }
        if (n) {
            WorkItem marker{plan_.firstFrame(*n), TileRect{}};
            marker.chunk = *n;
            marker.frames = plan_.framesIn(*n);
            marker.assembler = rank;
            open_.push_back({rank, plan_.firstFrame(*n), plan_.lastFrame(*n), *n});
            return marker;
        }
        // No chunk can open (all are, or the window is full): the next frame of the one with the
        // most left (the earliest on a tie, since the film is joined in order), rendered here for
        // its owner. Its frames keep coming in order, so its encoder takes them as they come and
        // none waits long in the owner's memory for an earlier one.
        OpenChunk* most = nullptr;
        for (OpenChunk& c : open_)
            if (!most || c.last - c.next > most->last - most->next) most = &c;
        if (!most) return std::nullopt;
        return frame(most->next++);
    }
    void reopenChunk(int chunk) override {
        open_.erase(std::remove_if(open_.begin(), open_.end(), [&](const OpenChunk& c) { return c.chunk == chunk; }), open_.end());
        reopen_.push_back(chunk);
    }
    int itemsPerFrame() const override { return 1; }
    Mode mode() const override { return Mode::Frame; }

protected:
    bool midFrame() const override {
        if (!reopen_.empty()) return true;
        for (const OpenChunk& c : open_)
            for (int f = c.next; f <= c.last; ++f)
                if (!kept_.contains(f)) return true;
        return false;
    }

private:
    struct OpenChunk {
        int owner;       ///< the rank it was opened for (its marker's assembler)
        int next, last;  ///< the frames not handed out yet lie in [next, last]
        int chunk;
    };
    /// Drops kept frames from both ends of c's frames still to hand out; false when none is left.
    bool trim(OpenChunk& c) const {
        while (c.next <= c.last && kept_.contains(c.next)) ++c.next;
        while (c.last >= c.next && kept_.contains(c.last)) --c.last;
        return c.next <= c.last;
    }
    WorkItem frame(int f) const { return WorkItem{f, full_}; }

    ChunkPlan plan_;
    anim::FrameRanges kept_;
    TileRect full_;
    std::vector<OpenChunk> open_;
    std::deque<int> reopen_;  ///< chunks whose rank was lost, to open again
};

}  // namespace

std::unique_ptr<Scheduler> makeChunkFrameScheduler(const ChunkPlan& plan, anim::FrameRanges kept, int width, int height,
                                                   int window) {
    return std::make_unique<ChunkFrameScheduler>(plan, std::move(kept), width, height, window);
}

std::unique_ptr<Scheduler> makeFrameScheduler(anim::FrameRanges frames, int width, int height, int window) {
    return std::make_unique<FrameScheduler>(std::move(frames), width, height, window);
}

}  // namespace rf::farm
