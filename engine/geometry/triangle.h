#pragma once
/// Ray–triangle tests: the seed's classic plane-and-edges test, Möller–Trumbore, and the
/// watertight test of Woop, Benthin and Wald (JCGT 2013) used for meshes.
#include "engine/geometry/ray.h"

namespace rf {

struct TriangleHit {
    float t = kInf;
    float b0 = 0.f, b1 = 0.f, b2 = 0.f;  ///< barycentric weights of p0, p1, p2
};

/// The seed's classic algorithm: plane hit, then point on the inner side of all three edges
/// (edges inclusive).
bool intersectTriangleClassic(const Ray& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float tMax,
                              TriangleHit& hit);

/// Möller–Trumbore as the seed writes it, with edge-inclusive tests and no absolute epsilon.
bool intersectTriangleMT(const Ray& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float tMax,
                         TriangleHit& hit);

/// Per-ray constants of the watertight test: the axis permutation and shear.
struct WatertightRay {
    Vec3 o;
    int kx = 0, ky = 1, kz = 2;
    float sx = 0.f, sy = 0.f, sz = 1.f;
    WatertightRay() = default;
    explicit WatertightRay(const Ray& r);
};

/// Watertight test: a ray through a shared edge or vertex hits at least one of the triangles.
bool intersectTriangleWatertight(const WatertightRay& wr, const Vec3& p0, const Vec3& p1, const Vec3& p2,
                                 float tMax, TriangleHit& hit);

/// Hit point from barycentrics, and its error bound (independent of the ray length).
inline Vec3 triangleHitPoint(const Vec3& p0, const Vec3& p1, const Vec3& p2, const TriangleHit& h, Vec3& pError) {
    const Vec3 a = h.b0 * p0, b = h.b1 * p1, c = h.b2 * p2;
    pError = gamma(7) * (absComponents(a) + absComponents(b) + absComponents(c));
    return a + b + c;
}

}  // namespace rf
