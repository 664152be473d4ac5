#include "farm/cluster/scheduler.h"

#include <cstdio>

namespace rf::farm {

namespace {

/// Pixel mode's speed against frame mode's when both keep every rank busy: bench_farm.sh on
/// 2CylinderEngine, 120 frames at 640x360, 2 ranks, 8 chunks (af714b2, Release PGO+LTO): pixel
/// 29.00 fps, frame 31.15 (0.93); with chunks assembled on the ranks (this rule's commit,
/// RelWithDebInfo, two rounds) 23.6 / 24.8 and 25.8 / 25.6 at 8 chunks. Tiles cost messages,
/// and a tile's rays are less coherent with its neighbours' than a whole frame's.
constexpr double kPixelModeShare = 0.93;

}  // namespace

Mode chooseMode(int frames, int renderers, int width, int height, std::string& why, int chunkFrames) {
    const long long pixels = 1LL * width * height;
    if (renderers <= 1) {
        why = "one rendering rank: whole frames, no tile traffic";
        return Mode::Frame;
    }
    if (chunkFrames > 1) {
        // Whole frames of about equal cost go out as ranks free up, the last ones shared among
        // the ranks whatever chunk they belong to, so the last round of frames leaves ranks idle
        // unless it is full.
        const long long rounds = (frames + renderers - 1LL) / renderers;
        const double busy = double(frames) / double(rounds * renderers);
        const std::string counted = std::to_string(frames) + " frame(s) for " + std::to_string(renderers) + " rendering ranks";
        char share[64];
        std::snprintf(share, sizeof share, "whole frames keep the ranks %.0f%% busy", 100.0 * busy);
        if (busy < kPixelModeShare) {
            why = counted + ": " + share + ", tiles about 93%; each chunk assembled on a rank";
            return Mode::Pixel;
        }
        why = counted + ": " + share + "; each chunk rendered and encoded on one rank, the least traffic";
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
