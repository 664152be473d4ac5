#pragma once
/// The bytes of a frame or tile as every rank and every sink sees them.
#include <cstddef>
#include <cstdint>

namespace rf::farm {

/// How the pixel bytes of a tile or frame are laid out: a plane of tone-mapped, sRGB-encoded
/// 8-bit pixels (RGB, or straight RGBA when the background is transparent), then, when linear
/// frames (EXR) are asked for, a plane of linear premultiplied RGBA floats. Every rank knows
/// the layout from the job; rank 0 checks it on every result.
struct PixelLayout {
    int32_t channels = 3;  ///< 3 or 4 in the 8-bit plane
    bool linear = false;

    size_t bytes(size_t pixels) const { return pixels * (size_t(channels) + (linear ? 4 * sizeof(float) : 0)); }
    /// Where the linear plane starts in a buffer of `pixels` pixels.
    size_t linearOffset(size_t pixels) const { return pixels * size_t(channels); }
    bool operator==(const PixelLayout& o) const { return channels == o.channels && linear == o.linear; }
};

}  // namespace rf::farm
