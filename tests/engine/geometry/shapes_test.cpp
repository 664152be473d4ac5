// Sphere and plane intersection, including the stiff cases 1, 2, 7, 8 and 12 of
// docs/stability.md.
#include <gtest/gtest.h>

#include <random>

#include "engine/geometry/shapes.h"

using namespace rf;

namespace {
/// Both roots of |o + t·d − c|² = r² in long double, the reference for the float and double
/// paths; c_ is |o − c|² − r² (negative when o is inside). disc < 0 when the line misses.
struct RootsLD {
    long double near = 0, far = 0, disc = 0, c = 0;
};
RootsLD referenceRoots(const Vec3& o, const Vec3& d, const Vec3& center, float radius) {
    using LD = long double;
    const LD fx = LD(o.x) - center.x, fy = LD(o.y) - center.y, fz = LD(o.z) - center.z;
    const LD a = LD(d.x) * d.x + LD(d.y) * d.y + LD(d.z) * d.z;
    const LD b = fx * d.x + fy * d.y + fz * d.z;
    RootsLD r;
    r.c = fx * fx + fy * fy + fz * fz - LD(radius) * radius;
    r.disc = b * b - a * r.c;
    if (r.disc >= 0) {
        r.near = (-b - std::sqrt(r.disc)) / a;
        r.far = (-b + std::sqrt(r.disc)) / a;
    }
    return r;
}
}  // namespace

TEST(Sphere, HitsUnitSphereHeadOn) {
    Sphere s{Vec3(0.f), 1.f, 0};
    Ray r{Vec3(0, 0, 5), Vec3(0, 0, -1)};
    float t;
    Vec3 rel;
    ASSERT_TRUE(intersectSphere(s, r, 0.f, kInf, t, &rel));
    EXPECT_FLOAT_EQ(t, 4.f);
    EXPECT_NEAR(rel.z, 1.f, 1e-6f);
}

TEST(Sphere, InsideOriginReturnsFarRoot) {
    Sphere s{Vec3(0.f), 2.f, 0};
    Ray r{Vec3(0.f), Vec3(1, 0, 0)};
    float t;
    ASSERT_TRUE(intersectSphere(s, r, 0.f, kInf, t));
    EXPECT_FLOAT_EQ(t, 2.f);
}

TEST(Sphere, MissesWhenRayPassesBeside) {
    Sphere s{Vec3(0.f), 1.f, 0};
    Ray r{Vec3(0, 1.0001f, 5), Vec3(0, 0, -1)};
    float t;
    EXPECT_FALSE(intersectSphere(s, r, 0.f, kInf, t));
}

// Catalogue 1: r = 0.1, ray along +x at y = 0.095 from far away.
TEST(Sphere, SmallSphereIsHitFromFarAway) {
    Sphere s{Vec3(0.f), 0.1f, 0};
    for (float x : {-400.f, -1e4f, -1e7f}) {
        Ray r{Vec3(x, 0.095f, 0.f), Vec3(1, 0, 0)};
        float t;
        Vec3 rel;
        EXPECT_TRUE(intersectSphere(s, r, 0.f, kInf, t, &rel)) << "origin x = " << x;
        // The hit point is on the surface and on the ray's line, however far the origin.
        EXPECT_NEAR(glm::length(rel), 0.1f, 1e-6f);
        EXPECT_NEAR(rel.y, 0.095f, 1e-6f);
        EXPECT_NEAR(rel.x, -std::sqrt(0.1 * 0.1 - 0.095 * 0.095), 1e-5f);
    }
}

// The textbook quadratic is what case 1 warns against: its discriminant is rounding noise once
// the origin is a few hundred radii away, so its "hit" lands off the sphere (or misses).
TEST(Sphere, NaiveQuadraticGoesWrongFarAway) {
    Sphere s{Vec3(0.f), 0.1f, 0};
    Ray r{Vec3(-400.f, 0.095f, 0.f), Vec3(1, 0, 0)};
    float t;
    const bool hit = intersectSphereNaive(s, r, 0.f, kInf, t);
    const float trueT = 400.f - std::sqrt(0.1f * 0.1f - 0.095f * 0.095f);
    EXPECT_TRUE(!hit || std::abs(t - trueT) > 1e-3f);
    ASSERT_TRUE(intersectSphere(s, r, 0.f, kInf, t));
    EXPECT_NEAR(t, trueT, 1e-4f);
}

// Catalogue 2: float roots within 1e-5 relative of a long double reference.
TEST(Sphere, RootsMatchLongDoubleReference) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::uniform_real_distribution<float> logd(-1.f, 4.f);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 c(u(rng), u(rng), u(rng));
        const float radius = 0.5f + 0.5f * (u(rng) + 1.f);
        Vec3 dirTo = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
        const float dist = radius * (1.f + std::pow(10.f, logd(rng)) * 1e-3f) + (i % 2 ? std::pow(10.f, logd(rng)) : 0.f);
        const Vec3 o = c + dirTo * dist;
        const Vec3 target = c + radius * 0.99f * glm::normalize(Vec3(u(rng), u(rng), u(rng)));
        const Vec3 d = glm::normalize(target - o);
        Sphere s{c, radius, 0};
        float t;
        if (!intersectSphere(s, Ray{o, d}, 0.f, kInf, t)) continue;
        const RootsLD ld = referenceRoots(o, d, c, radius);
        ASSERT_GE(ld.disc, 0.0L);
        const long double ref = ld.near > 0 ? ld.near : ld.far;
        EXPECT_NEAR(t / double(ref), 1.0, 1e-5) << "case " << i;
        ++hits;
    }
    EXPECT_GT(hits, 10000);
}

// Rays that nearly graze the silhouette (closest approach 0.9 to 1 − 1e-7 radii) from 1.1 to 30
// radii away: the near root stays within 1e-5 relative of the long double root, so t still orders
// a sphere against a surface it touches (the float path hands these to double).
TEST(Sphere, NearTangentRootsStayAccurate) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1.f, 1.f), u01(0.f, 1.f);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 c = 2.f * Vec3(u(rng), u(rng), u(rng));
        const float radius = std::pow(10.f, u(rng));
        const Vec3 d = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
        const Vec3 side = glm::normalize(glm::cross(d, Vec3(u(rng), u(rng), u(rng))));
        const float miss = std::pow(10.f, -1.f - 6.f * u01(rng));  // 1 − closest approach / r
        const float dist = radius * (1.1f + 29.f * u01(rng));
        const Vec3 o = c + radius * (1.f - miss) * side - dist * d;
        float t;
        if (!intersectSphere(Sphere{c, radius, 0}, Ray{o, d}, 0.f, kInf, t)) continue;
        const RootsLD ld = referenceRoots(o, d, c, radius);
        ASSERT_GE(ld.disc, 0.0L) << "case " << i;
        EXPECT_NEAR(t / double(ld.near), 1.0, 1e-5) << "case " << i << ", miss " << miss;
        ++hits;
    }
    EXPECT_GT(hits, 15000);
}

// Catalogue 12: a thin gap of 4e-5 between concentric spheres is still resolved.
TEST(Sphere, InnerSphereHitFromInsideThinGap) {
    Sphere inner{Vec3(0.f), 1.f, 0};
    Sphere outer{Vec3(0.f), 1.f + 4e-5f, 0};
    // A ray starting on the outer sphere's inside, heading inwards.
    Ray r{Vec3(0, 0, 1.f + 3.9e-5f), Vec3(0, 0, -1)};
    float t;
    ASSERT_TRUE(intersectSphere(inner, r, 0.f, kInf, t));
    EXPECT_NEAR(t, 3.9e-5f, 1e-6f);
    // A fixed epsilon of 1e-4 would have skipped it.
    EXPECT_FALSE(intersectSphere(inner, r, 1e-4f, 1.5e-4f, t));
    (void)outer;
}

// A ray spawned inwards from the surface (refraction into glass) meets the sphere only at its
// exit: the far root, in float, against a long double reference, from head-on to grazing.
TEST(Sphere, FromInsideFindsTheExit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::uniform_real_distribution<float> logc(-6.f, 0.f);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 c = 3.f * Vec3(u(rng), u(rng), u(rng));
        const float radius = std::pow(10.f, u(rng));
        const Vec3 n = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
        const Vec3 rel = radius * n;
        const Vec3 p = c + rel;
        // As SceneGeometry::interaction bounds a sphere hit point.
        const Vec3 pError = gamma(5) * absComponents(rel) + gamma(2) * absComponents(p);
        // Inward directions, the cosine to -n spread log-uniformly down to 1e-6 (grazing).
        const Vec3 t = glm::normalize(glm::cross(n, Vec3(u(rng), u(rng), u(rng))));
        const float cosIn = std::pow(10.f, logc(rng));
        const Vec3 d = glm::normalize(-cosIn * n + std::sqrt(1.f - cosIn * cosIn) * t);
        const Ray r{offsetRayOrigin(p, pError, n, d), d};
        const Sphere s{c, radius, 0};
        float tHit;
        Vec3 pRel;
        ASSERT_TRUE(intersectSphereFromInside(s, r, kInf, tHit, &pRel)) << "case " << i;
        const RootsLD ld = referenceRoots(r.o, d, c, radius);
        ASSERT_LT(ld.c, 0.0L) << "the spawned origin must lie inside, case " << i;
        const double far = double(ld.far);
        // The chord is 2r·cos: relative error 1e-5 of it, or a few ulps of r when it is tiny.
        EXPECT_NEAR(double(tHit), far, 1e-5 * far + 8.0 * kMachineEps * radius) << "case " << i;
        EXPECT_NEAR(glm::length(pRel) / radius, 1.f, 1e-6f);
        ++checked;
    }
    EXPECT_EQ(checked, 20000);
}

TEST(Plane, HitsFromAboveAndBelow) {
    Plane p{Vec3(0, 1, 0), 0.f, 0};
    float t;
    ASSERT_TRUE(intersectPlane(p, Ray{Vec3(0, 2, 0), Vec3(0, -1, 0)}, 0.f, kInf, t));
    EXPECT_FLOAT_EQ(t, 2.f);
    ASSERT_TRUE(intersectPlane(p, Ray{Vec3(0, -3, 0), Vec3(0, 1, 0)}, 0.f, kInf, t));
    EXPECT_FLOAT_EQ(t, 3.f);
}

// Catalogue 8: a ray parallel to, or lying in, the plane misses cleanly.
TEST(Plane, ParallelAndInPlaneRaysMissWithoutNaN) {
    Plane p{Vec3(0, 1, 0), 0.f, 0};
    float t = 123.f;
    EXPECT_FALSE(intersectPlane(p, Ray{Vec3(0, 1, 0), Vec3(1, 0, 0)}, 0.f, kInf, t));
    EXPECT_FALSE(intersectPlane(p, Ray{Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.f, kInf, t));
    EXPECT_EQ(t, 123.f);
}

// Catalogue 7: scaling the scene scales t and keeps hit/miss.
TEST(Plane, HitPointErrorScalesWithThePointNotTheRay) {
    Plane p{Vec3(0, 1, 0), 0.f, 0};
    Ray r{Vec3(-1e6f, 1e6f, 3.f), glm::normalize(Vec3(1e6f + 1.3f, -1e6f, 0.f))};
    float t;
    ASSERT_TRUE(intersectPlane(p, r, 0.f, kInf, t));
    Vec3 err;
    const Vec3 hp = planeHitPoint(p, r, t, err);
    EXPECT_LE(std::abs(hp.y), err.y);
    EXPECT_LT(err.y, 1e-5f);  // bounded by |p| ≈ 1, not by t ≈ 1.4e6
}

TEST(Scale, SphereHitsScaleWithTheScene) {
    for (float k : {1e-4f, 1.f, 1e4f}) {
        Sphere s{Vec3(0.f), 1.f * k, 0};
        float t;
        ASSERT_TRUE(intersectSphere(s, Ray{Vec3(0.3f * k, 0.2f * k, 5.f * k), Vec3(0, 0, -1)}, 0.f, kInf, t));
        const float expect = (5.f - std::sqrt(1.f - 0.09f - 0.04f)) * k;
        EXPECT_NEAR(t / expect, 1.f, 1e-6f) << "scale " << k;
        EXPECT_FALSE(intersectSphere(s, Ray{Vec3(1.01f * k, 0.f, 5.f * k), Vec3(0, 0, -1)}, 0.f, kInf, t)) << "scale " << k;
    }
}
