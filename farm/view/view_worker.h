#pragma once
/// Ranks 1…N−1 of `mpirun … rayfarm view`: render the window's work items (a camera, an epoch,
/// a rectangle) with renderTile on the rank's threads and send back 8-bit pixels. No window, no
/// Qt on these ranks.
#include "scene.h"
#include "timeline.h"
#include "transport.h"

namespace rf::view {

/// Serves rank 0 until it says stop (returns 0) or goes away (returns 1). Newer work drops
/// older epochs, the rectangle being rendered included (checked between 16×16 sub-tiles).
int runViewWorker(farm::Transport& t, Scene scene, RenderSettings settings, int threads);

}  // namespace rf::view
