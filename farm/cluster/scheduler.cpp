#include "scheduler.h"

namespace rf::farm {

Mode chooseMode(int frames, int renderers, int width, int height, std::string& why, int chunkFrames) {
    const long long pixels = 1LL * width * height;
    if (renderers <= 1) {
        why = "one rendering rank: whole frames, no tile traffic";
        return Mode::Frame;
    }
    if (chunkFrames > 1) {
        const int chunks = (frames + chunkFrames - 1) / chunkFrames;
        const std::string counted = std::to_string(frames) + " frame(s) in " + std::to_string(chunks) + " chunk(s) of " +
                                    std::to_string(chunkFrames) + " for " + std::to_string(renderers) + " rendering ranks";
        if (chunks < 4 * renderers) {
            why = counted + ": too few chunks to keep every rank busy with whole chunks";
            return Mode::Pixel;
        }
        why = counted + ": each rank renders and encodes whole chunks, the least traffic";
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
