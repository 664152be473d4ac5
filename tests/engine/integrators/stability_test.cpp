// Whole-scene stiff cases of docs/stability.md: distance invariance (3), the thin gap at scene
// level (12), the scale sweep (21) and a model far from the world origin (22). The cases are
// defined once in farm/report/stability/ (report --stability tabulates the same); the thresholds
// asserted here are this test's own, so loosening a case's tolerance there does not pass here.
#include <gtest/gtest.h>

#include "tests/engine/engine_test_util.h"
#include "farm/report/stability/stability_cases.h"

using namespace rf;
using stability::StabilityCase;

namespace {

/// Image cases: at most 0.1% of pixels off by more than 1/255 in some channel.
void expectImagesAgree(const std::vector<StabilityCase>& cases, size_t expected) {
    ASSERT_EQ(cases.size(), expected);
    for (const StabilityCase& c : cases) {
        if (c.informative) continue;
        EXPECT_EQ(c.unit, "% pixels off") << c.name;
        EXPECT_LE(c.error, 0.1) << "#" << c.id << " " << c.name << ": " << c.measured;
    }
}

}  // namespace

// Catalogue 3: a unit sphere seen from 10 and from 1000 (flat shading) and from 1000 and 1e5
// (lit), with the field of view scaled so its silhouette covers the same pixels.
TEST(Stability, SphereSilhouetteIsTheSameFromNearAndFar) {
    std::vector<StabilityCase> cases;
    stability::distanceInvariance(cases, 1);
    expectImagesAgree(cases, 2);
}

// Catalogue 12 at scene level: the inner of two concentric spheres 4e-5 apart is still hit by a
// ray spawned inside the gap, within 1e-6 of the gap, from 64 directions.
TEST(Stability, ThinGapBetweenConcentricSpheres) {
    std::vector<StabilityCase> cases;
    stability::thinGap(cases);
    ASSERT_EQ(cases.size(), 1u);
    EXPECT_EQ(cases[0].error, 0.0) << cases[0].measured;
    EXPECT_TRUE(cases[0].pass) << cases[0].measured;
    EXPECT_NE(cases[0].measured.find(" of 64 "), std::string::npos) << cases[0].measured;  // every ray hit the outer shell
}

// A ray entering a sphere goes straight to the exit only when nothing else reaches into the
// sphere: a plane cutting it, or a second sphere overlapping it, is still met first; a plane or
// sphere that only touches it is not.
TEST(Stability, RayInsideSphereStillMeetsWhatCutsIt) {
    auto firstHit = [](float planeY, bool overlap) {
        Scene s = test::emptyScene();
        s.geometry.spheres.push_back(Sphere{Vec3(0.f), 1.f, 0});
        s.geometry.spheres.push_back(Sphere{Vec3(overlap ? 1.5f : 2.f, 0.f, 0.f), 1.f, 0});  // 2: touching
        s.geometry.planes.push_back(Plane{Vec3(0, 1, 0), -planeY, 0});
        s.build();
        const Ray in{Vec3(0, -5, 0), Vec3(0, 1, 0)};
        Hit h;
        EXPECT_TRUE(s.geometry.intersect(in, h, SceneGeometry::kNoPrim));
        const SurfaceInteraction si = s.geometry.interaction(in, h);
        // Refracted straight on, then turned towards +x, as a ray inside glass would be.
        const Vec3 d = glm::normalize(Vec3(0.8f, 1.f, 0.f));
        const Ray r{offsetRayOrigin(si.p, si.pError, si.ng, d), d};
        Hit h2;
        EXPECT_TRUE(s.geometry.intersect(r, h2, s.geometry.skipFor(si, d)));
        const bool blocked = s.geometry.occluded(r, 100.f, s.geometry.skipFor(si, d));
        EXPECT_TRUE(blocked);
        return r.o + h2.t * r.d;
    };
    // Plane tangent below (y = -1 would be the sphere's bottom; here -5 < y < -1 is left alone).
    EXPECT_NEAR(glm::length(firstHit(-1.f, false)), 1.f, 1e-5f);  // touching plane: the exit
    EXPECT_NEAR(firstHit(0.f, false).y, 0.f, 1e-5f);                 // cutting plane: met first
    const Vec3 p = firstHit(-1.f, true);                             // overlapping sphere
    EXPECT_NEAR(glm::length(p - Vec3(1.5f, 0.f, 0.f)), 1.f, 1e-5f);
    EXPECT_LT(glm::length(p), 1.f - 1e-3f);                           // inside the first sphere
}

// Catalogue 21: the whole scene (camera, lights, geometry, checker) scaled by 1e-4 and 1e5
// renders as at scale 1: at least 99.9% of pixels within 1/255.
TEST(Stability, SceneScaleSweep) {
    std::vector<StabilityCase> cases;
    stability::scaleSweep(cases, 1);
    expectImagesAgree(cases, 2);
}

// Catalogue 22: a scene translated to x = 6.4e6 renders like the untranslated one (the loader
// rebases positions to a render origin chosen from the camera target, in double); the float
// world-coordinate contrast must really differ, or the case could not tell.
TEST(Stability, SceneFarFromTheOriginRendersTheSame) {
    EXPECT_EQ(stability::translatedScene(6.4e6).renderOrigin.x, 6.4e6);
    std::vector<StabilityCase> cases;
    stability::translatedModel(cases, 1);
    expectImagesAgree(cases, 2);
    ASSERT_TRUE(cases[1].informative);
    EXPECT_GT(cases[1].error, 0.1) << cases[1].measured;
}

// Catalogue 11 on triangles, as the report tabulates it: the uniformly lit quad at z = 1e-3,
// 1e3, 1e5 and tilts 0°, 30°, 60° has a standard deviation of at most 0.5 levels.
TEST(Stability, FlatQuadRowsPass) {
    std::vector<StabilityCase> cases;
    stability::flatQuads(cases, 1);
    ASSERT_EQ(cases.size(), 9u);
    for (const StabilityCase& c : cases) EXPECT_LE(c.error, 0.5) << c.name << ": " << c.measured;
}

// The report's light-units row: a 10 cd lamp keeps its light at the default --min-weight.
TEST(Stability, DimLightRowPasses) {
    std::vector<StabilityCase> cases;
    stability::dimLightScene(cases, 2);
    ASSERT_EQ(cases.size(), 1u);
    EXPECT_TRUE(cases[0].pass) << cases[0].measured;
    EXPECT_LE(cases[0].error, 0.1) << cases[0].measured;
}

// The report's smooth-glass row: the UV sphere mesh of glass within 4 levels RMS of the sphere.
TEST(Stability, SmoothGlassRowPasses) {
    std::vector<StabilityCase> cases;
    stability::smoothGlassMesh(cases, 2);
    ASSERT_EQ(cases.size(), 1u);
    EXPECT_LE(cases[0].error, 4.0) << cases[0].measured;
}

// The report's tile-size comparison: not one pixel of either scene differs across tilings,
// packets and the blocker cache.
TEST(Stability, TilingRowsFindNoDifference) {
    std::vector<StabilityCase> cases;
    stability::tilingIndependence(cases, 2);
    ASSERT_EQ(cases.size(), 2u);
    for (const StabilityCase& c : cases) {
        EXPECT_EQ(c.error, 0.0) << c.name << ": " << c.measured;
        EXPECT_NE(c.measured.find("15 variants"), std::string::npos) << c.measured;
    }
}
