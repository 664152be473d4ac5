#pragma once
/// A ray with its parametric extent.
#include "engine/util/vec_math.h"

namespace rf {

struct Ray {
    Vec3 o{0.f};
    Vec3 d{0.f, 0.f, -1.f};
    float tMax = kInf;
    /// The ray's cone (Akenine-Möller et al. 2019, "Texture Level of Detail Strategies for
    /// Real-Time Ray Tracing"): its width at o and how much it widens per unit distance; what
    /// a texture lookup at the hit filters over. Zero: a thin ray (textures read unfiltered).
    float coneWidth = 0.f;
    float coneSpread = 0.f;
};

/// Where a spawned ray starts: the hit point pushed off the surface by its error bound.
/// pError bounds the absolute error of p per axis; n is the geometric normal; w the new direction.
/// After pbrt-v4's OffsetRayOrigin: the offset scales with the point, never a fixed epsilon.
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& pError, const Vec3& n, const Vec3& w) {
    const float d = glm::dot(absComponents(n), pError);
    Vec3 offset = d * n;
    if (glm::dot(w, n) < 0.f) offset = -offset;
    Vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.f) po[i] = nextFloatUp(po[i]);
        else if (offset[i] < 0.f) po[i] = nextFloatDown(po[i]);
    }
    return po;
}

}  // namespace rf
