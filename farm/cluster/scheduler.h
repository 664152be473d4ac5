#pragma once
/// What to hand out next. Both modes hand out work dynamically, as workers ask, and keep a
/// bounded window of open frames (started but not yet written out), so memory on rank 0 does not
/// grow with the frame count and frames can be written in order.
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "anim/frame_ranges.h"
#include "farm/cluster/messages.h"
#include "farm/output/video_chunk.h"

namespace rf::farm {

enum class Mode { Pixel, Frame };

class Scheduler {
public:
    /// frames: the frames to render; they go out in increasing order.
    Scheduler(anim::FrameRanges frames, int window)
        : frames_(std::move(frames)), next_(frames_.start()), window_(std::max(1, window)) {}
    virtual ~Scheduler() = default;

    /// The next item to hand out, or nullopt if none may go out now: everything is handed out,
    /// or starting another frame would exceed the window.
    virtual std::optional<WorkItem> next() = 0;
    /// The next item for `rank` (the rank whose credit is free). Schedulers that keep work
    /// where it is assembled use it; the others hand out the same as next().
    virtual std::optional<WorkItem> nextFor(int rank) {
        (void)rank;
        return next();
    }
    /// What the master hands `rank` next: work taken back from a lost rank first (requeue),
    /// then nextFor's.
    std::optional<WorkItem> take(int rank) {
        if (retry_.empty()) return nextFor(rank);
        WorkItem item = retry_.front();
        retry_.pop_front();
        return item;
    }
    /// An item a lost rank held, handed out again before anything new (its frame is open
    /// already: the window does not count it twice).
    void requeue(const WorkItem& item) { retry_.push_back(item); }
    /// Chunked encoding: the rank assembling the chunk was lost, with every frame it held of
    /// it. Its marker goes out again (a new rank assembles it) and then every frame of it not
    /// kept, as if it had just opened (the window counts it once still).
    virtual void reopenChunk(int chunk) { (void)chunk; }
    /// Work items one frame is split into.
    virtual int itemsPerFrame() const = 0;
    virtual Mode mode() const = 0;

    /// Frame was written out: its place in the window is free.
    void frameReleased() { --open_; }
    /// Everything has been handed out.
    bool exhausted() const { return retry_.empty() && frames_.atEnd(next_) && !midFrame(); }
    int openFrames() const { return open_; }
    int window() const { return window_; }

protected:
    /// True while the current frame still has items to hand out (pixel mode).
    virtual bool midFrame() const { return false; }
    /// Opens the next frame if the window allows; returns its index or nullopt.
    std::optional<int> openNextFrame() {
        if (frames_.atEnd(next_) || open_ >= window_) return std::nullopt;
        ++open_;
        const int f = frames_.at(next_);
        frames_.advance(next_);
        return f;
    }

private:
    anim::FrameRanges frames_;
    std::deque<WorkItem> retry_;  ///< taken back from lost ranks
    anim::FrameCursor next_;
    int window_;
    int open_ = 0;
};

/// Pixel mode: every frame split into tiles of tileSize; the next frame's tiles go out as soon as
/// the current frame's are all handed out, before it is complete, so no rank idles at frame ends.
std::unique_ptr<Scheduler> makePixelScheduler(anim::FrameRanges frames, int width, int height, int tileSize,
                                              int window);

/// Frame mode: whole frames, one per item.
std::unique_ptr<Scheduler> makeFrameScheduler(anim::FrameRanges frames, int width, int height, int window);

/// Frame mode with chunked encoding: whole frames, each chunk assembled and encoded by one
/// rank, its owner, which renders the chunk's frames in order itself (nextFor: a rank's own
/// open chunk first; with none, it opens the next chunk, its marker carrying the rank as
/// WorkItem::assembler). When no chunk can open (every chunk is, or the window is full), a
/// rank with no frame of its own left renders the next frames of the open chunk with the most
/// left, for its owner: the film's end is shared frame by frame instead of waiting for the
/// slowest chunk. Kept frames (--resume) are not handed out. The window counts chunks.
std::unique_ptr<Scheduler> makeChunkFrameScheduler(const ChunkPlan& plan, anim::FrameRanges kept, int width, int height,
                                                   int window);

/// Pixel mode with chunked encoding: each chunk assembled and encoded by one rank from the
/// tiles of every rank. Opening a chunk hands out its marker (WorkItem::chunk set, an empty
/// rect: the master sends the chunk to the rank it picks to assemble it), then the tiles of its
/// frames not in `kept`, the open chunks taking turns frame by frame. The window counts chunks.
std::unique_ptr<Scheduler> makeChunkTileScheduler(const ChunkPlan& plan, anim::FrameRanges kept, int width, int height,
                                                  int tileSize, int window);

/// mode "auto": pixel mode when frame mode's items are few compared with the rendering ranks
/// (it would leave ranks idle); frame mode otherwise (fewer, bigger messages). chunkFrames > 1:
/// the video is encoded in chunks of that many frames on the ranks, so rank 0 holds no frames
/// whatever their size; frame mode is chosen when whole frames, handed out in rounds, keep the
/// ranks busy at least as much of the time as pixel mode's measured speed against frame
/// mode's (93%). chunkFrames 1: whole frames go to rank 0 (a GIF, EXR frames), and large
/// frames get pixel mode to keep its window small.
/// why receives a one-line reason.
Mode chooseMode(int frames, int renderers, int width, int height, std::string& why, int chunkFrames = 1);

}  // namespace rf::farm
