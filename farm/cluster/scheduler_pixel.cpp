#include "render.h"
#include "scheduler.h"

namespace rf::farm {

namespace {

class PixelScheduler : public Scheduler {
public:
    PixelScheduler(anim::FrameRanges frames, int width, int height, int tileSize, int window)
        : Scheduler(std::move(frames), window), tiles_(makeTiles(width, height, tileSize)) {}

    std::optional<WorkItem> next() override {
        if (tile_ >= tiles_.size()) {
            const std::optional<int> f = openNextFrame();
            if (!f) return std::nullopt;
            frame_ = *f;
            tile_ = 0;
        }
        return WorkItem{frame_, tiles_[tile_++]};
    }
    int itemsPerFrame() const override { return int(tiles_.size()); }
    Mode mode() const override { return Mode::Pixel; }

protected:
    bool midFrame() const override { return tile_ < tiles_.size(); }

private:
    std::vector<TileRect> tiles_;
    size_t tile_ = SIZE_MAX;  // no frame open yet
    int frame_ = -1;
};

}  // namespace

std::unique_ptr<Scheduler> makePixelScheduler(anim::FrameRanges frames, int width, int height, int tileSize,
                                              int window) {
    return std::make_unique<PixelScheduler>(std::move(frames), width, height, tileSize, window);
}

}  // namespace rf::farm
