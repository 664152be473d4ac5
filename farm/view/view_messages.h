#pragma once
/// What rank 0 of `rayfarm view` broadcasts with the scene. Everything after goes through the
/// farm's own messages (farm/cluster/messages.h): kTagView epochs for the window's views, work items
/// for films, and kTagViewTimeline when the window's camera keys change the timeline.
#include <cstdint>
#include <string>

#include "engine/scene/background.h"
#include "engine/util/settings.h"

namespace rf::view {

/// Broadcast with the scene: what every rank renders with.
struct ViewJob {
    RenderSettings settings;  ///< the target picture
    BackgroundChoice background;
    int32_t threads = 0;      ///< --threads, 0: the rank's share of its node
};

std::string encodeViewJob(const ViewJob& j);
/// Throws std::runtime_error on a malformed payload.
ViewJob decodeViewJob(const std::string& bytes);

}  // namespace rf::view
