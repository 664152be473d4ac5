#pragma once
/// Linear frames for compositing: half-float OpenEXR (RGBA, premultiplied alpha as OpenEXR
/// expects, ZIP compression) through Debian's OpenEXR. The frames directory gets
/// frame_NNNNNN.exr next to each PNG.
#include <string>
#include <vector>

#include "anim/frame_ranges.h"
#include "farm/output/frame_sink.h"
#include "farm/output/pixel_layout.h"

namespace rf::farm {

/// DIR/frame_NNNNNN.exr
std::string frameExrPath(const std::string& dir, int frame);

/// Writes width × height RGBA floats (linear, premultiplied) as half-float EXR, whole or not at
/// all (a temporary name, then a rename). Throws std::runtime_error naming the path.
void writeExrRgba(const std::string& path, int width, int height, const float* rgba);
/// Reads an RGBA EXR back as floats (alpha 1 where the file has none). Throws naming the path.
std::vector<float> readExrRgba(const std::string& path, int& width, int& height);

/// Frames whose EXR is in dir, readable, of width × height.
anim::FrameRanges findKeptExrFrames(const std::string& dir, const anim::FrameRanges& frames, int width, int height);

/// The frames directory's EXR half: writes each frame's linear plane (PixelLayout).
class ExrSink : public FrameSink {
public:
    ExrSink(std::string dir, int width, int height, PixelLayout layout)
        : dir_(std::move(dir)), width_(width), height_(height), layout_(layout) {}
    void write(int frame, const std::vector<uint8_t>& pixels) override;
    void close() override {}

private:
    std::string dir_;
    int width_, height_;
    PixelLayout layout_;
};

}  // namespace rf::farm
