#pragma once
/// PNG bytes through FFmpeg's PNG encoder at a fast setting (zlib level 1, no prediction):
/// about 3 ms for a 640x360 frame against about 15 ms for stb_image_write, which matters when
/// every frame of a 30 fps run is kept. Lossless either way. Rendered frames' flat and smooth
/// areas deflate well without a filter: the Whitted orbit's frame 10 is 119 KB in 3.8 ms
/// unfiltered, 130 KB in 4.5 ms with "sub" (2CylinderEngine: 60 KB in 2.6 ms against 66 KB
/// in 2.7 ms).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rf::farm {

class PngEncoder {
public:
    /// channels: 3 (RGB) or 4 (straight RGBA). Throws std::runtime_error if FFmpeg has no PNG
    /// encoder.
    PngEncoder(int width, int height, int channels = 3);
    ~PngEncoder();
    PngEncoder(const PngEncoder&) = delete;
    PngEncoder& operator=(const PngEncoder&) = delete;

    /// width × height × channels bytes (more are ignored) to a complete PNG file image.
    std::string encode(const std::vector<uint8_t>& rgb);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// A PNG file image back to width × height × channels bytes (a kept frame sent to the rank that
/// encodes its chunk); throws std::runtime_error naming `what` when it is no PNG of that size.
std::vector<uint8_t> decodePngFrame(const std::string& png, const std::string& what, int width, int height, int channels);

}  // namespace rf::farm
