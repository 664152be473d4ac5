#pragma once
/// Rank 0's reorder buffer: tiles and frames arrive in any order; frames leave complete and in
/// output order. Frames already on disk (--resume) take their turn in the order too.
#include <map>
#include <vector>

#include "anim/frame_ranges.h"
#include "farm/cluster/messages.h"

namespace rf::farm {

/// A frame ready to be written, in output order.
struct ReadyFrame {
    int frame = 0;
    bool onDisk = false;        ///< kept from an earlier run: the caller reads it back
    std::vector<uint8_t> rgb;   ///< the frame in the assembler's PixelLayout unless onDisk
};

class FrameAssembler {
public:
    /// order: every frame of the output (they leave in increasing order); onDisk: those kept
    /// from an earlier run. Every result must come in `layout`.
    FrameAssembler(int width, int height, anim::FrameRanges order, anim::FrameRanges onDisk, PixelLayout layout = {});

    /// Copies a result into its frame; returns true if that completed the frame. Throws
    /// std::runtime_error if it does not belong to a frame being rendered, lies outside the image
    /// or covers pixels twice.
    bool add(const TileResult& r);
    /// Pixels of a frame completed and not yet popped (nullptr otherwise).
    const std::vector<uint8_t>* completed(int frame) const;
    /// Pixels of a frame begun and not yet popped, complete or not (nullptr otherwise): only
    /// the rectangles added so far are rendered (an interactive session's partial pictures).
    const std::vector<uint8_t>* pixels(int frame) const;
    /// The next frame in order if it is complete (or on disk).
    bool popReady(ReadyFrame& out);
    /// All frames have been popped.
    bool finished() const { return order_.atEnd(next_); }
    /// Frames being assembled or waiting for their turn.
    int held() const { return int(partial_.size()); }
    /// Frames popped so far.
    int popped() const { return popped_; }

private:
    struct Partial {
        std::vector<uint8_t> rgb;
        std::vector<uint8_t> covered;  ///< one byte per pixel, to refuse overlapping tiles
        long long remaining = 0;
    };
    int width_, height_;
    PixelLayout layout_;
    /// A frame rendered here: in the order, not on disk, and not popped yet.
    bool wanted(int frame) const;

    anim::FrameRanges order_;
    anim::FrameRanges onDisk_;
    std::map<int, Partial> partial_;
    anim::FrameCursor next_;  ///< the next frame to pop
    int popped_ = 0;
};

}  // namespace rf::farm
