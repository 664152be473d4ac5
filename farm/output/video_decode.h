#pragma once
/// Decodes a video file back to 8-bit RGB frames, so that what encoding lost can be measured (rayfarm report).
#include <cstdint>
#include <string>
#include <vector>

namespace rf::farm {

/// Every frame of the first video stream of path as width × height × 3 bytes of full-range
/// RGB, converted from BT.709 limited-range YUV (what the MP4 sink writes) and cropped to
/// width × height (the sink pads odd sizes). Throws std::runtime_error naming the path.
std::vector<std::vector<uint8_t>> decodeVideoRgb8(const std::string& path, int width, int height);

}  // namespace rf::farm
