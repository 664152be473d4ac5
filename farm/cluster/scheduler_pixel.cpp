#include <algorithm>
#include <deque>

#include "engine/integrators/render.h"
#include "farm/cluster/scheduler.h"

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

/// Pixel mode with chunked encoding. The scheduler's "frames" are chunk numbers, as in frame
/// mode's ChunkFrameScheduler: the window counts chunks open. Opening a chunk yields its marker (the
/// chunk's WorkItem, an empty rectangle), on which the master picks the rank that assembles it;
/// then the frames of the open chunks go out tile by tile, taking the chunks in turn a frame at
/// a time, so every open chunk's assembler receives frames at once and the encoders run side
/// by side. Kept frames (--resume) are not handed out: their chunk's assembler reads them.
class ChunkTileScheduler : public Scheduler {
public:
    ChunkTileScheduler(const ChunkPlan& plan, anim::FrameRanges kept, int width, int height, int tileSize, int window)
        : Scheduler(anim::FrameRanges::span(0, plan.count() - 1), window), plan_(plan), kept_(std::move(kept)),
          tiles_(makeTiles(width, height, tileSize)) {}

    std::optional<WorkItem> next() override {
        if (tile_ < tiles_.size()) return WorkItem{frame_, tiles_[tile_++]};
        // A chunk whose assembling rank was lost first (it holds the film up), then the next.
        std::optional<int> c;
        if (!reopen_.empty()) {
            c = reopen_.front();
            reopen_.pop_front();
        } else {
            c = openNextFrame();
        }
        if (c) {
            WorkItem marker{plan_.firstFrame(*c), TileRect{}};
            marker.chunk = *c;
            marker.frames = plan_.framesIn(*c);
            open_.push_back({plan_.firstFrame(*c), plan_.lastFrame(*c)});
            return marker;
        }
        // The next frame to render of the open chunks, in turn; a chunk with none left closes.
        while (!open_.empty()) {
            const size_t i = turn_ % open_.size();
            OpenChunk& c = open_[i];
            while (c.next <= c.last && kept_.contains(c.next)) ++c.next;
            if (c.next > c.last) {
                open_.erase(open_.begin() + long(i));
                turn_ = i;  // the chunk after it has its turn
                continue;
            }
            turn_ = i + 1;
            frame_ = c.next++;
            tile_ = 0;
            return WorkItem{frame_, tiles_[tile_++]};
        }
        return std::nullopt;
    }
    void reopenChunk(int chunk) override {
        const int first = plan_.firstFrame(chunk), last = plan_.lastFrame(chunk);
        // The rest of a frame of it being handed out goes with the whole chunk.
        if (tile_ < tiles_.size() && frame_ >= first && frame_ <= last) tile_ = tiles_.size();
        open_.erase(std::remove_if(open_.begin(), open_.end(), [&](const OpenChunk& c) { return c.last == last; }), open_.end());
        turn_ = 0;
        reopen_.push_back(chunk);
    }
    int itemsPerFrame() const override { return int(tiles_.size()); }
    Mode mode() const override { return Mode::Pixel; }

protected:
    bool midFrame() const override {
        if (tile_ < tiles_.size() || !reopen_.empty()) return true;
        for (const OpenChunk& c : open_)
            for (int f = c.next; f <= c.last; ++f)
                if (!kept_.contains(f)) return true;
        return false;
    }

private:
    struct OpenChunk {
        int next, last;  ///< the next frame to hand out, and the chunk's last
    };
    ChunkPlan plan_;
    anim::FrameRanges kept_;
    std::vector<TileRect> tiles_;
    std::vector<OpenChunk> open_;
    std::deque<int> reopen_;  ///< chunks whose assembling rank was lost, to open again
    size_t turn_ = 0;
    size_t tile_ = SIZE_MAX;
    int frame_ = -1;
};

}  // namespace

std::unique_ptr<Scheduler> makeChunkTileScheduler(const ChunkPlan& plan, anim::FrameRanges kept, int width, int height,
                                                  int tileSize, int window) {
    return std::make_unique<ChunkTileScheduler>(plan, std::move(kept), width, height, tileSize, window);
}

std::unique_ptr<Scheduler> makePixelScheduler(anim::FrameRanges frames, int width, int height, int tileSize,
                                              int window) {
    return std::make_unique<PixelScheduler>(std::move(frames), width, height, tileSize, window);
}

}  // namespace rf::farm
