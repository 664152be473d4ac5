#pragma once
/// Axis-aligned bounding box and a NaN-safe, conservative slab test.
#include <algorithm>

#include "engine/geometry/ray.h"

namespace rf {

struct Aabb {
    Vec3 lo{kInf};
    Vec3 hi{-kInf};

    // Forced inline and written out per axis (glm::min/max's exact comparisons, NaN included:
    // min(x, y) = y < x ? y : x, max(x, y) = x < y ? y : x): GCC with the PGO profile kept grow
    // and area out of line, and those calls were a third of a skinned mesh's per-frame tree
    // work (builds and refits; perf on anim_bench --model).
    [[gnu::always_inline]] void grow(const Vec3& p) { grow(p, p); }
    [[gnu::always_inline]] void grow(const Aabb& b) { grow(b.lo, b.hi); }
    [[gnu::always_inline]] void grow(const Vec3& l, const Vec3& h) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = l[a] < lo[a] ? l[a] : lo[a];
            hi[a] = hi[a] < h[a] ? h[a] : hi[a];
        }
    }
    [[gnu::always_inline]] bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3 center() const { return 0.5f * (lo + hi); }
    [[gnu::always_inline]] Vec3 extent() const { return hi - lo; }
    [[gnu::always_inline]] float area() const {
        if (empty()) return 0.f;
        const Vec3 e = extent();
        return 2.f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    int longestAxis() const {
        const Vec3 e = extent();
        return (e.x >= e.y && e.x >= e.z) ? 0 : (e.y >= e.z ? 1 : 2);
    }
};

/// Per-ray constants for box tests.
struct RayBoxPrecomp {
    Vec3 o;
    Vec3 invD;
    explicit RayBoxPrecomp(const Ray& r) : o(r.o), invD(1.f / r.d.x, 1.f / r.d.y, 1.f / r.d.z) {}
};

/// Slab test. A zero direction component gives ±inf in invD; an origin exactly on that slab then
/// gives 0·inf = NaN, which the argument order of the min/max below ignores (the slab is treated
/// as inclusive). tFar is widened by 1 + 2·gamma(3) (pbrt-v4; Ize 2013) so traversal stays
/// conservative under rounding.
inline bool intersectAabb(const Aabb& b, const RayBoxPrecomp& r, float tMin, float tMax, float& tEntry) {
    float t0 = tMin, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        float tNear = (b.lo[a] - r.o[a]) * r.invD[a];
        float tFar = (b.hi[a] - r.o[a]) * r.invD[a];
        if (tNear > tFar) std::swap(tNear, tFar);
        tFar *= 1.f + 2.f * gamma(3);
        t0 = tNear > t0 ? tNear : t0;  // NaN compares false: keeps t0
        t1 = tFar < t1 ? tFar : t1;
        if (t0 > t1) return false;
    }
    tEntry = t0;
    return true;
}

}  // namespace rf
