#include "scheduler.h"

namespace rf::farm {

Mode chooseMode(int frames, int renderers, int width, int height, std::string& why) {
    const long long pixels = 1LL * width * height;
    if (renderers <= 1) {
        why = "one rendering rank: whole frames, no tile traffic";
        return Mode::Frame;
    }
    if (frames < 4 * renderers) {
        why = std::to_string(frames) + " frame(s) for " + std::to_string(renderers) +
              " rendering ranks: too few frames to keep every rank busy with whole frames";
        return Mode::Pixel;
    }
    if (pixels >= 3840LL * 2160) {
        why = "frames of " + std::to_string(width) + "x" + std::to_string(height) +
              " are large: tiles keep the reorder window small";
        return Mode::Pixel;
    }
    why = std::to_string(frames) + " frames for " + std::to_string(renderers) +
          " rendering ranks: whole frames balance well with the least traffic";
    return Mode::Frame;
}

}  // namespace rf::farm
