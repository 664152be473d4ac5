#include "scheduler.h"

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

class ChunkScheduler : public Scheduler {
public:
    // The scheduler's "frames" are the chunks' numbers: the window and the order work on them.
    ChunkScheduler(const ChunkPlan& plan, int width, int height, int window)
        : Scheduler(anim::FrameRanges::span(0, plan.count() - 1), window), plan_(plan), full_{0, 0, width, height} {}

    std::optional<WorkItem> next() override {
        const std::optional<int> c = openNextFrame();
        if (!c) return std::nullopt;
        WorkItem item{plan_.firstFrame(*c), full_};
        item.chunk = *c;
        item.frames = plan_.framesIn(*c);
        return item;
    }
    int itemsPerFrame() const override { return 1; }
    Mode mode() const override { return Mode::Frame; }

private:
    ChunkPlan plan_;
    TileRect full_;
};

}  // namespace

std::unique_ptr<Scheduler> makeChunkScheduler(const ChunkPlan& plan, int width, int height, int window) {
    return std::make_unique<ChunkScheduler>(plan, width, height, window);
}

std::unique_ptr<Scheduler> makeFrameScheduler(anim::FrameRanges frames, int width, int height, int window) {
    return std::make_unique<FrameScheduler>(std::move(frames), width, height, window);
}

}  // namespace rf::farm
