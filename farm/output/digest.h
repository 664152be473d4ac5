#pragma once
/// SHA-256 through FFmpeg's libavutil (already linked for the video): the resume manifest keeps
/// one per input file and one per kept frame, so a changed scene or a corrupt PNG is noticed.
#include <string>
#include <string_view>

namespace rf::farm {

/// Lower-case hex SHA-256 of `bytes`.
std::string sha256Hex(std::string_view bytes);

}  // namespace rf::farm
