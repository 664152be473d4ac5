// Ray–triangle tests (classic, Möller–Trumbore, watertight) and the mesh cases 4–8 and 18 of
// docs/stability.md.
#include <gtest/gtest.h>

#include <random>

#include "tests/engine/engine_test_util.h"
#include "engine/geometry/triangle.h"

using namespace rf;

namespace {
const Vec3 kP0(0, 0, 0), kP1(1, 0, 0), kP2(0, 1, 0);

bool hitWatertight(const Ray& r, const Vec3& a, const Vec3& b, const Vec3& c, TriangleHit& h, float tMax = kInf) {
    return intersectTriangleWatertight(WatertightRay(r), a, b, c, tMax, h);
}
}  // namespace

TEST(Triangle, AllThreeTestsAgreeOnAnInteriorHit) {
    const Ray r{Vec3(0.25f, 0.5f, 2.f), Vec3(0, 0, -1)};
    TriangleHit c, m, w;
    ASSERT_TRUE(intersectTriangleClassic(r, kP0, kP1, kP2, kInf, c));
    ASSERT_TRUE(intersectTriangleMT(r, kP0, kP1, kP2, kInf, m));
    ASSERT_TRUE(hitWatertight(r, kP0, kP1, kP2, w));
    for (const TriangleHit& h : {c, m, w}) {
        EXPECT_FLOAT_EQ(h.t, 2.f);
        // p = b0·p0 + b1·p1 + b2·p2 = (0.25, 0.5): b1 = x, b2 = y.
        EXPECT_NEAR(h.b1, 0.25f, 1e-6f);
        EXPECT_NEAR(h.b2, 0.5f, 1e-6f);
        EXPECT_NEAR(h.b0, 0.25f, 1e-6f);
    }
}

TEST(Triangle, OutsideAndBehindAndBeyondTMaxMiss) {
    TriangleHit h;
    const Ray outside{Vec3(0.8f, 0.8f, 2.f), Vec3(0, 0, -1)};
    EXPECT_FALSE(intersectTriangleClassic(outside, kP0, kP1, kP2, kInf, h));
    EXPECT_FALSE(intersectTriangleMT(outside, kP0, kP1, kP2, kInf, h));
    EXPECT_FALSE(hitWatertight(outside, kP0, kP1, kP2, h));
    const Ray behind{Vec3(0.2f, 0.2f, -1.f), Vec3(0, 0, -1)};
    EXPECT_FALSE(intersectTriangleMT(behind, kP0, kP1, kP2, kInf, h));
    EXPECT_FALSE(hitWatertight(behind, kP0, kP1, kP2, h));
    const Ray ok{Vec3(0.2f, 0.2f, 3.f), Vec3(0, 0, -1)};
    EXPECT_FALSE(hitWatertight(ok, kP0, kP1, kP2, h, 2.5f));
    EXPECT_TRUE(hitWatertight(ok, kP0, kP1, kP2, h, 3.5f));
}

// Catalogue 4: the seam between two triangles of a square.
TEST(Triangle, SeamRayHitsAtLeastOneTriangle) {
    const Vec3 a(-5, -5, 0), b(5, -5, 0), c(5, 5, 0), d(-5, 5, 0);
    const Ray r{Vec3(0, 0, 10), Vec3(0.30458447f, 0.30458447f, -0.9024725f)};
    TriangleHit h1, h2;
    const bool w1 = hitWatertight(r, a, b, c, h1), w2 = hitWatertight(r, a, c, d, h2);
    ASSERT_TRUE(w1 || w2);
    const TriangleHit& h = w1 ? h1 : h2;
    EXPECT_NEAR(h.t, 11.0807f, 1e-3f);
    const Vec3 p = r.o + h.t * r.d;
    EXPECT_NEAR(p.x, 3.375f, 1e-3f);
    EXPECT_NEAR(p.y, 3.375f, 1e-3f);
    EXPECT_NEAR(p.z, 0.f, 1e-5f);
}

// Catalogue 6: u = 0, v = 0 and u + v = 1 are inside (no epsilon strip along edges).
TEST(Triangle, EdgesAndVerticesAreInclusive) {
    // Points exactly on the three edges and at the three vertices of (0,0,0),(1,0,0),(0,1,0).
    const Vec2 pts[] = {{0.5f, 0.f}, {0.f, 0.5f}, {0.5f, 0.5f}, {0.f, 0.f}, {1.f, 0.f}, {0.f, 1.f}, {0.25f, 0.75f}};
    for (const Vec2& q : pts) {
        const Ray r{Vec3(q.x, q.y, 1.f), Vec3(0, 0, -1)};
        TriangleHit h;
        EXPECT_TRUE(intersectTriangleMT(r, kP0, kP1, kP2, kInf, h)) << q.x << "," << q.y;
        EXPECT_TRUE(hitWatertight(r, kP0, kP1, kP2, h)) << q.x << "," << q.y;
        EXPECT_TRUE(intersectTriangleClassic(r, kP0, kP1, kP2, kInf, h)) << q.x << "," << q.y;
        EXPECT_FLOAT_EQ(h.t, 1.f);
    }
}

// Catalogue 8: a ray parallel to, or lying in, the triangle's plane misses without NaN.
TEST(Triangle, ParallelAndInPlaneRaysMissCleanly) {
    const Ray above{Vec3(-1.f, 0.2f, 0.5f), Vec3(1, 0, 0)};
    const Ray inPlane{Vec3(-1.f, 0.2f, 0.f), Vec3(1, 0, 0)};
    for (const Ray& r : {above, inPlane}) {
        TriangleHit h;
        h.t = 42.f;
        EXPECT_FALSE(intersectTriangleClassic(r, kP0, kP1, kP2, kInf, h));
        EXPECT_FALSE(intersectTriangleMT(r, kP0, kP1, kP2, kInf, h));
        EXPECT_FALSE(hitWatertight(r, kP0, kP1, kP2, h));
        EXPECT_EQ(h.t, 42.f);
    }
    // Degenerate (zero-area) triangles never report a hit either.
    TriangleHit h;
    const Ray down{Vec3(0.5f, 0.f, 1.f), Vec3(0, 0, -1)};
    EXPECT_FALSE(hitWatertight(down, kP0, kP1, Vec3(2, 0, 0), h));
    EXPECT_FALSE(intersectTriangleMT(down, kP0, kP1, Vec3(2, 0, 0), kInf, h));
}

// Catalogue 7: scaling by 1e-4 and 1e4 keeps hit/miss and scales t.
TEST(Triangle, HitsScaleWithTheScene) {
    for (float k : {1e-4f, 1.f, 1e4f}) {
        const Vec3 a = k * kP0, b = k * kP1, c = k * kP2;
        TriangleHit h;
        ASSERT_TRUE(hitWatertight(Ray{k * Vec3(0.3f, 0.3f, 7.f), Vec3(0, 0, -1)}, a, b, c, h)) << k;
        EXPECT_NEAR(h.t / (7.f * k), 1.f, 1e-6f) << k;
        EXPECT_FALSE(hitWatertight(Ray{k * Vec3(0.6f, 0.6f, 7.f), Vec3(0, 0, -1)}, a, b, c, h)) << k;
        ASSERT_TRUE(intersectTriangleMT(Ray{k * Vec3(0.3f, 0.3f, 7.f), Vec3(0, 0, -1)}, a, b, c, kInf, h)) << k;
        EXPECT_NEAR(h.t / (7.f * k), 1.f, 1e-6f) << k;
    }
}

// Catalogue 5: rays through the shared vertices and edges of a closed mesh, and a grid of rays
// whose lines pass within the inscribed radius, all hit it — triangle by triangle and through
// the scene's BVH.
TEST(Triangle, WatertightClosedMeshHasNoCracks) {
    Scene s = test::emptyScene();
    const Vec3 centre(0.37f, -0.21f, 0.13f);
    s.geometry.meshes.push_back(test::uvSphere(12, 17, 1.3f, centre, false));
    s.build();
    ASSERT_TRUE(s.geometry.usesBvh());
    const TriangleMesh& m = s.geometry.meshes[0];
    // Inscribed radius of the polyhedron: the smallest distance from the centre to a face plane.
    float inscribed = kInf;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]], c = m.positions[m.indices[3 * t + 2]];
        const Vec3 n = glm::normalize(glm::cross(b - a, c - a));
        inscribed = std::min(inscribed, std::abs(glm::dot(n, a - centre)));
    }
    std::vector<Ray> rays;
    auto aimThrough = [&](const Vec3& p) {  // from outside, through p, towards the centre
        const Vec3 d = glm::normalize(centre - p);
        rays.push_back(Ray{p - 3.f * d, d});
    };
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t* ix = &m.indices[3 * t];
        for (int k = 0; k < 3; ++k) {
            aimThrough(m.positions[ix[k]]);
            aimThrough(0.5f * (m.positions[ix[k]] + m.positions[ix[(k + 1) % 3]]));
        }
    }
    const int n = 200;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const float x = (2.f * i / (n - 1) - 1.f) * inscribed * 0.999f, y = (2.f * j / (n - 1) - 1.f) * inscribed * 0.999f;
            if (x * x + y * y >= inscribed * inscribed * 0.998f) continue;
            rays.push_back(Ray{centre + Vec3(x, y, 5.f), Vec3(0, 0, -1)});
            rays.push_back(Ray{centre + Vec3(5.f, x, y), Vec3(-1, 0, 0)});
        }
    size_t missBrute = 0, missScene = 0;
    for (const Ray& r : rays) {
        const WatertightRay wr(r);
        bool any = false;
        for (size_t t = 0; t < m.triangleCount() && !any; ++t) {
            TriangleHit h;
            any = intersectTriangleWatertight(wr, m.positions[m.indices[3 * t]], m.positions[m.indices[3 * t + 1]],
                                              m.positions[m.indices[3 * t + 2]], kInf, h);
        }
        missBrute += !any;
        Hit hit;
        missScene += !s.geometry.intersect(r, hit);
    }
    EXPECT_GT(rays.size(), 40000u);
    EXPECT_EQ(missBrute, 0u);
    EXPECT_EQ(missScene, 0u);
}

// Barycentric interpolation of vertex normals (the seed's Phong shading) and of UVs.
TEST(Triangle, InteractionInterpolatesNormalsAndUvs) {
    Scene s = test::emptyScene();
    TriangleMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
    m.normals = {Vec3(0, 0, 1), glm::normalize(Vec3(1, 0, 1)), glm::normalize(Vec3(0, 1, 1))};
    m.uvs = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
    m.indices = {0, 1, 2};
    s.geometry.meshes.push_back(m);
    s.build();
    const Ray r{Vec3(0.5f, 0.5f, 3.f), Vec3(0, 0, -1)};
    Hit hit;
    ASSERT_TRUE(s.geometry.intersect(r, hit));
    const SurfaceInteraction si = s.geometry.interaction(r, hit);
    // Barycentrics (0.5, 0.25, 0.25).
    const Vec3 expectN = glm::normalize(0.5f * m.normals[0] + 0.25f * m.normals[1] + 0.25f * m.normals[2]);
    EXPECT_NEAR(glm::length(si.ns - expectN), 0.f, 1e-6f);
    EXPECT_NEAR(si.uv.x, 0.25f, 1e-6f);
    EXPECT_NEAR(si.uv.y, 0.25f, 1e-6f);
    EXPECT_NEAR(std::abs(si.ng.z), 1.f, 1e-6f);
    EXPECT_NEAR(si.p.x, 0.5f, 1e-6f);
    EXPECT_NEAR(si.p.y, 0.5f, 1e-6f);
}

// Catalogue 18: zero vertex normals (a cone apex) and a zero-area triangle: the shading normal
// stays unit length or falls back on the geometric normal, never NaN.
TEST(Triangle, ZeroNormalsAndZeroAreaStayFinite) {
    Scene s = test::emptyScene();
    TriangleMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 2, 0), Vec3(3, 3, 0), Vec3(4, 4, 0)};
    m.normals = {Vec3(0.f), Vec3(0.f), Vec3(0.f), Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(0.f)};
    m.indices = {0, 1, 2, 3, 4, 5};
    s.geometry.meshes.push_back(m);
    s.build();
    Hit hit;
    const Ray r{Vec3(0.2f, 0.2f, 1.f), Vec3(0, 0, -1)};
    ASSERT_TRUE(s.geometry.intersect(r, hit));
    const SurfaceInteraction si = s.geometry.interaction(r, hit);
    EXPECT_NEAR(glm::length(si.ns), 1.f, 1e-6f);
    EXPECT_TRUE(isFinite(si.ns));
    EXPECT_NEAR(std::abs(glm::dot(si.ns, si.ng)), 1.f, 1e-6f);  // fell back on ng
    // A zero-area triangle met through a forged hit still yields finite, unit normals.
    Hit forged;
    forged.prim = 1;
    forged.t = 1.f;
    forged.tri.b0 = forged.tri.b1 = 0.5f;
    forged.tri.b2 = 0.f;
    const SurfaceInteraction sz = s.geometry.interaction(Ray{Vec3(3, 3, 1), Vec3(0, 0, -1)}, forged);
    EXPECT_TRUE(isFinite(sz.ng));
    EXPECT_TRUE(isFinite(sz.ns));
    EXPECT_NEAR(glm::length(sz.ng), 1.f, 1e-6f);
    EXPECT_NEAR(glm::length(sz.ns), 1.f, 1e-6f);
}
