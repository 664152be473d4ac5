#include "shapes.h"

namespace rf {

bool sphereMayHit(const Sphere& s, const Ray& r, float tMax) {
    const Vec3 f = r.o - s.center;
    const float a = glm::dot(r.d, r.d);
    const float b = glm::dot(f, r.d);
    const Vec3 v = f - (b / a) * r.d;
    // 32 ulps of the largest magnitude involved bounds the float error of f, b and v generously;
    // the test only rejects, the exact answer comes from the double path.
    const float err = 32.f * kMachineEps * (maxComponent(glm::abs(r.o)) + maxComponent(glm::abs(s.center)) + s.radius);
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

bool intersectSphereExact(const Sphere& s, const Ray& r, float tMin, float tMax, float& t, Vec3* pRel) {
    // Double precision for the few operations that cancel: o − c when the origin sits near the
    // surface (a spawned ray), and |f|² − r² when it is far away. Spheres are few; this is cheap.
    using glm::dvec3;
    const dvec3 f = dvec3(r.o) - dvec3(s.center);
    const dvec3 d(r.d);
    const double radius = s.radius;
    const double a = glm::dot(d, d);
    const double invA = 1.0 / a;
    const double bHalf = glm::dot(f, d);
    // v is the closest-approach point relative to the centre: r² − |v|² is the discriminant
    // without the catastrophic cancellation of the textbook b² − 4ac (Ray Tracing Gems ch. 7).
    const dvec3 v = f - (bHalf * invA) * d;
    const double vLen = glm::length(v);
    const double disc = a * (radius + vLen) * (radius - vLen);
    if (!(disc >= 0.0)) return false;
    const double sq = std::sqrt(disc);
    const double c = glm::dot(f, f) - radius * radius;
    const double q = -(bHalf + std::copysign(sq, bHalf));
    double t0 = q * invA;
    double t1 = (q != 0.0) ? c / q : t0;
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
        const double s0 = sq * invA;
        dvec3 p = v + (nearRoot ? -s0 : s0) * d;
        const double len = glm::length(p);
        if (len > 0.0) p *= radius / len;  // reproject onto the surface
        *pRel = Vec3(p);
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

bool intersectPlane(const Plane& pl, const Ray& r, float tMin, float tMax, float& t) {
    const float denom = glm::dot(pl.n, r.d);
    if (denom == 0.f || !std::isfinite(denom)) return false;  // parallel, or lying in the plane
    const float tt = -(glm::dot(pl.n, r.o) + pl.d) / denom;
    if (!(tt > tMin && tt < tMax)) return false;
    t = tt;
    return true;
}

Vec3 planeHitPoint(const Plane& pl, const Ray& r, float t, Vec3& pError) {
    Vec3 p = r.o + t * r.d;
    // One projection step removes the error that grew with t; what is left scales with |p|.
    p -= pl.n * (glm::dot(pl.n, p) + pl.d);
    pError = gamma(6) * (glm::abs(p) + Vec3(std::abs(pl.d)));
    return p;
}

}  // namespace rf
