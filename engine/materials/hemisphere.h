#pragma once
/// Well-spread directions over a hemisphere: what the sampled indirect light
/// (indirect_light.cpp) and the bounce cache's gathers (bounce_cache.cpp) trace.
#include <cstdint>

#include "engine/util/vec_math.h"

namespace rf {

/// The i-th of n stratified points in [0, 1)²: the Hammersley set shifted by `rotation` modulo 1
/// (Cranley–Patterson), so each shading point gets its own well-spread set from one random offset.
Vec2 stratifiedPoint(uint32_t i, uint32_t n, Vec2 rotation);

/// A direction about +Z with density cos θ/π, from a point in [0, 1)² (Malley's method over
/// Shirley and Chiu's concentric disc: strata of the square stay compact on the hemisphere).
Vec3 cosineHemisphere(Vec2 u);

}  // namespace rf
