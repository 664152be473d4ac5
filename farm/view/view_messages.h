#pragma once
/// The viewer's messages between rank 0 (the window) and the other ranks, beside the farm's own
/// (farm/messages.h names the tags). A view work item carries the camera and an epoch: each
/// camera or frame change starts a new epoch, and a rank drops work of older epochs, the tile
/// it is rendering included, as soon as newer work reaches it.
#include <cstdint>
#include <string>
#include <vector>

#include "background_option.h"
#include "camera.h"
#include "render.h"
#include "settings.h"

namespace rf::view {

/// Broadcast with the scene: what every rank renders with.
struct ViewJob {
    RenderSettings settings;  ///< the target picture
    cli::BackgroundChoice background;
    int32_t threads = 0;      ///< --threads, 0: the rank's share of its node
};

/// Rank 0 → rank: render rect of the (width × height, spp) image of frame, through camera (or
/// the timeline's camera at frame).
struct ViewWork {
    uint64_t epoch = 0;
    int32_t frame = 0, spp = 1, width = 1, height = 1;
    int32_t followTimeline = 0;
    TileRect rect;
    Camera camera;
};

/// Rank → rank 0: the rect's 8-bit RGB (toRgb8 of renderTile's output); work.camera is the
/// camera rendered (the timeline's at work.frame when work.followTimeline).
struct ViewTile {
    ViewWork work;
    std::vector<uint8_t> rgb;
};

std::string encodeViewJob(const ViewJob& j);
ViewJob decodeViewJob(const std::string& bytes);
std::string encodeViewWork(const ViewWork& w);
ViewWork decodeViewWork(const std::string& bytes);
std::string encodeViewTile(const ViewTile& t);
/// Throws std::runtime_error on a malformed payload.
ViewTile decodeViewTile(const std::string& bytes);

}  // namespace rf::view
