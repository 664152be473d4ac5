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

}  // namespace

std::unique_ptr<Scheduler> makeFrameScheduler(anim::FrameRanges frames, int width, int height, int window) {
    return std::make_unique<FrameScheduler>(std::move(frames), width, height, window);
}

}  // namespace rf::farm
