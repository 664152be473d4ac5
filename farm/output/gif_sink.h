#pragma once
/// The film as a looping GIF with a palette made for it: FFmpeg's palettegen (statistics over
/// every frame) and paletteuse filters through libavfilter, then the GIF encoder and muxer.
/// A palette for the whole film needs every frame first, so the file is written at close():
/// when the film completes, or, after an interrupt, from the frames done so far.
#include <memory>
#include <string>

#include "farm/output/frame_sink.h"

namespace rf::farm {

/// Throws std::runtime_error naming path if libavfilter (opened at run time, not linked) cannot
/// be loaded: rank 0 checks it before the scene is shared, so no rank starts on a film whose
/// GIF could never be written.
void requireGifFilters(const std::string& path);

class GifSink : public FrameSink {
public:
    /// channels: 3, or 4 for one-bit transparency (alpha below half is transparent).
    /// dither: paletteuse's (sierra2_4a, bayer, floyd_steinberg, none). Checks that the output
    /// can be opened at once; throws std::runtime_error naming the path.
    GifSink(const std::string& path, int width, int height, int channels, double fps, const std::string& dither);
    ~GifSink() override;
    void write(int frame, const std::vector<uint8_t>& pixels) override;
    void close() override;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rf::farm
