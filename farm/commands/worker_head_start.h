#pragma once
/// The bounce cache built ahead of the film: on a worker while rank 0 decides the job and meters
/// its exposure, and on rank 0 before the meter when it renders too.
#include "farm/cli/cli.h"
#include "farm/cluster/render_job.h"
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene.h"
#include "anim/timeline.h"

namespace rf::cli {

/// Builds the scene's bounce cache for these settings at `frame`, the scene posed as the
/// exposure meter poses it (anim::TrialPose: in place, camera and lights put back, or on a copy
/// when a model's animation poses it, since posing leaves traces), so that the film's first frame on this rank
/// finds it ready instead of building it inside the run (about 0.4 s on one core for
/// 2CylinderEngine) into the film's slot; a cache for other settings or another pose is simply
/// not used, and the render builds its own as before.
void prebuildBounceCache(Scene& scene, const anim::Timeline& tl, const RenderSettings& settings, int frame,
                         int threads, SceneCacheSlot& bounceSlot);

/// A worker's head start (shareScene) while rank 0 decides the job and meters its exposure: the
/// bounce cache for the settings and first frame the same command line gives rank 0.
void workerHeadStart(LoadedScene& loaded, SceneCacheSlot& bounceSlot, const ArgParser& p, const farm::RenderJob& job, int threads);

}  // namespace rf::cli
