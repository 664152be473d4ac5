#pragma once
/// Ray–sphere and ray–plane intersection, numerically stable for far and grazing rays.
#include "engine/geometry/ray.h"

namespace rf {

struct Sphere {
    Vec3 center{0.f};
    float radius = 1.f;
    int material = 0;
};

/// Infinite plane n·p + d = 0 with unit normal n.
struct Plane {
    Vec3 n{0.f, 1.f, 0.f};
    float d = 0.f;
    int material = 0;
};

/// Nearest root of the sphere in (tMin, tMax). On a hit, *pRel (if given) is the hit point
/// relative to the centre, computed from the closest-approach point so it stays accurate when
/// the origin is far away (Haines et al., Ray Tracing Gems ch. 7).
bool intersectSphere(const Sphere& s, const Ray& r, float tMin, float tMax, float& t, Vec3* pRel = nullptr);

/// intersectSphere without the float pre-test, for callers that have filtered already.
bool intersectSphereExact(const Sphere& s, const Ray& r, float tMin, float tMax, float& t, Vec3* pRel = nullptr);

/// Exit of a ray that starts on the sphere's surface, just inside it, and heads inwards (a
/// refracted or internally reflected ray): only the far root can count. While the ray heads in
/// well off grazing, that root, (−b + √disc)/a, adds two positive terms and is computed in
/// float; otherwise (grazing, an origin not inside) it falls back on intersectSphereExact.
bool intersectSphereFromInside(const Sphere& s, const Ray& r, float tMax, float& t, Vec3* pRel = nullptr);

/// Conservative float pre-test: false only if the ray certainly misses in (0, tMax).
bool sphereMayHit(const Sphere& s, const Ray& r, float tMax);

/// Textbook quadratic (the seed's form), kept to show what the stable version fixes.
bool intersectSphereNaive(const Sphere& s, const Ray& r, float tMin, float tMax, float& t);

/// Plane hit in (tMin, tMax). A ray parallel to or lying in the plane misses cleanly.
inline bool intersectPlane(const Plane& pl, const Ray& r, float tMin, float tMax, float& t) {
    const float denom = glm::dot(pl.n, r.d);
    if (denom == 0.f || !std::isfinite(denom)) return false;  // parallel, or lying in the plane
    const float tt = -(glm::dot(pl.n, r.o) + pl.d) / denom;
    if (!(tt > tMin && tt < tMax)) return false;
    t = tt;
    return true;
}

/// Whether the plane crosses the ray in (0, tMax), without the division (the shadow-ray query):
/// t = num/denom lies there exactly when num has denom's sign and |num| < tMax·|denom|.
inline bool planeBlocks(const Plane& pl, const Ray& r, float tMax) {
    const float denom = glm::dot(pl.n, r.d);
    const float num = -(glm::dot(pl.n, r.o) + pl.d);
    if (denom > 0.f) return num > 0.f && num < tMax * denom;
    if (denom < 0.f) return num < 0.f && num > tMax * denom;
    return false;  // parallel, lying in the plane, or NaN
}

/// Hit point on the plane, projected back onto it, with its absolute error bound.
Vec3 planeHitPoint(const Plane& pl, const Ray& r, float t, Vec3& pError);

}  // namespace rf
