#pragma once
/// Benchmark stand-in work (bench/bench_coordinator.sh), compiled in only by a build
/// configured with -DRAYFARM_BENCH_HOOKS=ON, and even there off unless RAYFARM_BENCH_FREE_WORK
/// is set in the environment: every rank's engine fills each item with a cheap pattern that
/// moves with the frame instead of tracing it, so what remains per frame is the farm's own work
/// (dispatch, gather, assembly, PNG, encode, join). The pattern is not the scene's picture; it
/// only gives PNG and the encoders content to chew. It plugs in where engines are made
/// (RenderEngine::ItemRenderer), so the engine's own render path knows nothing of it.
#include "farm/cluster/render_engine.h"

namespace rf::farm {

#ifdef RAYFARM_BENCH_HOOKS
/// The stand-in renderer when the environment asks for it (and the job keeps no linear plane),
/// else null: RenderEngine's own tracing.
RenderEngine::ItemRenderer benchFreeWorkRenderer(bool linear);
#else
/// A production build: always RenderEngine's own tracing (bench_free_work.cpp is not compiled,
/// so neither the stand-in nor its environment variable is in the binary).
inline RenderEngine::ItemRenderer benchFreeWorkRenderer(bool) { return nullptr; }
#endif

}  // namespace rf::farm
