#pragma once
/// Benchmark stand-in work (bench/bench_coordinator.sh), off unless RAYFARM_BENCH_FREE_WORK
/// is set in the environment: every rank's engine fills each item with a cheap pattern that
/// moves with the frame instead of tracing it, so what remains per frame is the farm's own work
/// (dispatch, gather, assembly, PNG, encode, join). The pattern is not the scene's picture; it
/// only gives PNG and the encoders content to chew. It plugs in where engines are made
/// (RenderEngine::ItemRenderer), so the engine's own render path knows nothing of it.
#include "farm/cluster/render_engine.h"

namespace rf::farm {

/// The stand-in renderer when the environment asks for it (and the job keeps no linear plane),
/// else null: RenderEngine's own tracing.
RenderEngine::ItemRenderer benchFreeWorkRenderer(bool linear);

}  // namespace rf::farm
