#pragma once
/// Ranks 1…N−1 of `mpirun … rayfarm view`: the farm's own worker loop (runWorker over a
/// RenderEngine), serving rank 0's view sessions (kTagView epochs: camera, size, spp) and its
/// films (plain work items) alike, until rank 0 says stop. No window, no Qt on these ranks.
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene.h"
#include "anim/timeline.h"
#include "farm/cluster/transport.h"

namespace rf::view {

/// Serves rank 0 until it says stop (returns 0), a signal (130) or a failure (1, told to
/// rank 0 first). kTagViewTimeline (the window's camera keys changed) poses the scene as
/// loaded with the timeline it carries from the next work item on.
int runViewWorker(farm::Transport& t, LoadedScene loaded, RenderSettings settings, int threads);

}  // namespace rf::view
