#pragma once
/// --exposure auto: one EV for a whole film, metered before the first frame is rendered.
#include <functional>
#include <memory>
#include <string>

#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"
#include "anim/timeline.h"

namespace rf::cli {

/// The one warning line for a film whose metered frames are black: every light by name, type
/// and intensity in its file's units (cd, lx; scene-file lights are unitless).
std::string noLightWarning(const Scene& scene);

/// If settings.autoExposure, renders a few small frames spread evenly over the film (the same
/// frames whichever part of it this run renders, so a still and the film's frame agree), meters
/// them, stores the EV in settings.exposure, clears autoExposure and prints the EV chosen.
/// afterPose (if given) runs after each frame is posed, e.g. to look through a glTF camera.
/// The scene is left as it was (posed on a copy, or in place with its camera and lights put back:
/// anim::TrialPose, so a big model that does not move is not copied). bounceSlot: the job's bounce
/// cache, which the metering frames build or use as the job's frames will (null: their own).
void resolveAutoExposure(Scene& scene, const anim::Timeline& timeline, RenderSettings& settings, int threads,
                         const std::function<void(Scene&)>& afterPose = {},
                         const std::shared_ptr<SceneCacheSlot>& bounceSlot = nullptr);

}  // namespace rf::cli
