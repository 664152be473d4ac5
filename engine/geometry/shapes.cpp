#include "engine/geometry/shapes.h"

#include <type_traits>

namespace rf {

bool sphereMayHit(const Sphere& s, const Ray& r, float tMax) {
    const Vec3 f = r.o - s.center;
    const float a = glm::dot(r.d, r.d);
    const float b = glm::dot(f, r.d);
    const Vec3 v = f - (b / a) * r.d;
    // 32 ulps of the largest magnitude involved bounds the float error of f, b and v generously;
    // the test only rejects, the exact answer comes from the double path.
    const float err = 32.f * kMachineEps * (maxComponent(absComponents(r.o)) + maxComponent(absComponents(s.center)) + s.radius);
    const float reach = s.radius + err;
    const float reach2 = reach * reach;
    if (glm::dot(v, v) > reach2) return false;  // the line passes beside the sphere
    const float f2 = glm::dot(f, f);
    if (f2 > reach2 && b > 0.f) return false;  // outside and moving away
    // Entry no earlier than (|f| − reach)/|d|: beyond tMax cannot hit.
    if (f2 > reach2 && (std::sqrt(f2) - reach) > tMax * std::sqrt(a) * (1.f + 1e-5f)) return false;
    return std::isfinite(a) && a > 0.f;
}

bool intersectSphere(const Sphere& s, const Ray& r, float tMin, float tMax, float& t, Vec3* pRel) {
    // Most rays miss most spheres: a cheap, conservative float test rejects those first.
    return sphereMayHit(s, r, tMax) && intersectSphereExact(s, r, tMin, tMax, t, pRel);
}

namespace {

/// The stable root of intersectSphereExact in the precision T: f = o − c is formed in T, and
/// r² − |v|² (v the closest-approach point relative to the centre) is the discriminant without
/// the catastrophic cancellation of the textbook b² − 4ac (Ray Tracing Gems ch. 7).
template <class T>
bool sphereRoot(const Sphere& s, const Ray& r, float tMin, float tMax, float& t, Vec3* pRel) {
    using V = glm::vec<3, T>;
    const V f = V(r.o) - V(s.center);
    const V d(r.d);
    const T radius = s.radius;
    const T r2 = radius * radius;
    const T a = glm::dot(d, d);
    const T invA = T(1) / a;
    const T bHalf = glm::dot(f, d);
    const V v = f - (bHalf * invA) * d;
    const T disc = a * (r2 - glm::dot(v, v));
    if constexpr (std::is_same_v<T, float>) {
        // Near the silhouette √disc turns the float error of |v|² into a large error of the root
        // (up to ~1e-3 r at the tangent), which would decide which of two touching surfaces is in
        // front. Within 97% of the radius (disc ≥ a·r²/16) it stays at ~10 ulps; outside, double.
        if (!(disc >= T(0.0625) * a * r2)) return sphereRoot<double>(s, r, tMin, tMax, t, pRel);
    }
    if (!(disc >= T(0))) return false;
    const T sq = std::sqrt(disc);
    const T c = glm::dot(f, f) - r2;
    const T q = -(bHalf + std::copysign(sq, bHalf));
    T t0 = q * invA;
    T t1 = (q != T(0)) ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    bool nearRoot = true;
    if (t0 > tMin && t0 < tMax) {
        t = static_cast<float>(t0);
    } else if (t1 > tMin && t1 < tMax) {
        t = static_cast<float>(t1);
        nearRoot = false;
    } else {
        return false;
    }
    if (!(t > tMin && t < tMax)) return false;  // rounding to float crossed a bound
    if (pRel) {
        // Along-ray distance from the closest-approach point to the root, without subtracting
        // two large t values.
        const T s0 = sq * invA;
        V p = v + (nearRoot ? -s0 : s0) * d;
        const T len = glm::length(p);
        if (len > T(0)) p *= radius / len;  // reproject onto the surface
        *pRel = Vec3(p);
    }
    return true;
}

}  // namespace

bool intersectSphereExact(const Sphere& s, const Ray& r, float tMin, float tMax, float& t, Vec3* pRel) {
    // Double precision is needed where terms cancel: o − c and |f|² − r² for an origin on or
    // near the surface (a spawned ray), and the closest-approach point for an origin many radii
    // away. In between, the common case of a ray meeting a sphere from a few radii off, float
    // loses nothing that matters: |f|² − r² ≥ r²/16 keeps c (and the near root) within ~100 ulps
    // (6e-6 relative) at the inner bound, far less beyond, and |f| ≤ 32 r keeps the error of v
    // (a few ulps of |f|) within ~1e-5 r; the hit point is reprojected onto the surface.
    const Vec3 f = r.o - s.center;
    const float f2 = glm::dot(f, f), r2 = s.radius * s.radius;
    if (f2 > 1.0625f * r2 && f2 < 1024.f * r2) return sphereRoot<float>(s, r, tMin, tMax, t, pRel);
    return sphereRoot<double>(s, r, tMin, tMax, t, pRel);
}

bool intersectSphereFromInside(const Sphere& s, const Ray& r, float tMax, float& t, Vec3* pRel) {
    const Vec3 f = r.o - s.center;
    const float r2 = s.radius * s.radius;
    const float a = glm::dot(r.d, r.d);
    const float bHalf = glm::dot(f, r.d);
    const float f2 = glm::dot(f, f);
    // Float only for an origin inside up to a few ulps of r² (the spawn offset puts it inside by
    // its error bound) and a ray at least 75.5° off grazing (cos ≥ 1/4): b = f·d cancels as
    // cos → 0 and r² − |v|² loses ~4u/cos² of the squared chord, ≤ 2e-6 here. A refracted ray
    // entering glass of n ≥ 1.2 and its internal reflections always qualify.
    if (!(bHalf <= 0.f) || !(f2 <= r2 * (1.f + 1e-5f)) || !(a > 0.f) || !(bHalf * bHalf >= 0.0625f * a * f2))
        return intersectSphereExact(s, r, 0.f, tMax, t, pRel);
    const float invA = 1.f / a;
    const Vec3 v = f - (bHalf * invA) * r.d;
    // Inside, the line always crosses the sphere: a negative discriminant is rounding (the
    // tangent case), so it counts as zero.
    const float sq = std::sqrt(std::max(0.f, a * (r2 - glm::dot(v, v))));
    const float tt = (sq - bHalf) * invA;
    if (!(tt > 0.f && tt < tMax)) return false;
    t = tt;
    if (pRel) {
        Vec3 p = v + (sq * invA) * r.d;
        const float len = glm::length(p);
        if (len > 0.f) p *= s.radius / len;  // reproject onto the surface
        *pRel = p;
    }
    return true;
}

bool intersectSphereNaive(const Sphere& s, const Ray& r, float tMin, float tMax, float& t) {
    const Vec3 f = r.o - s.center;
    const float a = glm::dot(r.d, r.d);
    const float b = 2.f * glm::dot(f, r.d);
    const float c = glm::dot(f, f) - s.radius * s.radius;
    const float disc = b * b - 4.f * a * c;
    if (disc < 0.f) return false;
    const float sq = std::sqrt(disc);
    const float t0 = (-b - sq) / (2.f * a), t1 = (-b + sq) / (2.f * a);
    if (t0 > tMin && t0 < tMax) { t = t0; return true; }
    if (t1 > tMin && t1 < tMax) { t = t1; return true; }
    return false;
}

Vec3 planeHitPoint(const Plane& pl, const Ray& r, float t, Vec3& pError) {
    Vec3 p = r.o + t * r.d;
    // One projection step removes the error that grew with t; what is left scales with |p|.
    p -= pl.n * (glm::dot(pl.n, p) + pl.d);
    pError = gamma(6) * (absComponents(p) + Vec3(std::abs(pl.d)));
    return p;
}

}  // namespace rf
