#pragma once
/// Ray–sphere and ray–plane intersection, numerically stable for far and grazing rays.
#include "ray.h"

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
bool intersectPlane(const Plane& pl, const Ray& r, float tMin, float tMax, float& t);

/// Hit point on the plane, projected back onto it, with its absolute error bound.
Vec3 planeHitPoint(const Plane& pl, const Ray& r, float t, Vec3& pError);

}  // namespace rf
