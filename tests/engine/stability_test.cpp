// Whole-scene stiff cases of shared/stability.md: distance invariance (3), the thin gap at
// scene level (12), the scale sweep (21) and a model far from the world origin (22).
#include <gtest/gtest.h>

#include "engine_test_util.h"
#include "scene_loader.h"

using namespace rf;

namespace {
Scene loadText(const std::string& text) {
    FileBundle b;
    b.files["s.json"] = text;
    BundleFileSource fs(b);
    return loadScene("s.json", fs);
}
}  // namespace

// Catalogue 3: a unit sphere seen from 10 and from 1000 with the field of view scaled so its
// silhouette covers the same pixels. Flat (ambient-only) shading isolates the geometry.
TEST(Stability, SphereSilhouetteIsTheSameFromNearAndFar) {
    auto renderAt = [](float dist) {
        Scene s = test::emptyScene();
        s.materials[0] = test::matte(Color(0.9f, 0.6f, 0.3f), 1.f, 0.f);
        s.background = Color(0.1f);
        s.spheres.push_back(Sphere{Vec3(0.2f, -0.1f, 0.f), 1.f, 0});
        s.camera.eye = Vec3(0.2f, -0.1f, dist);
        s.camera.target = Vec3(0.2f, -0.1f, 0.f);
        // Angular radius asin(1/d); the silhouette fills 0.6 of the half-height.
        const double ang = std::asin(1.0 / dist);
        s.camera.fovDeg = float(glm::degrees(2.0 * std::atan(std::tan(ang) / 0.6)));
        s.build();
        return test::render(s, test::smallSettings(96, 64));
    };
    const Image near = renderAt(10.f), far = renderAt(1000.f);
    EXPECT_LE(test::fractionOff(near, far, 1), 0.001);
}

// Catalogue 12 at scene level: the inner of two concentric spheres 4e-5 apart is still hit by a
// ray spawned inside the gap.
TEST(Stability, ThinGapBetweenConcentricSpheres) {
    Scene s = test::emptyScene();
    s.spheres.push_back(Sphere{Vec3(0.f), 1.f, 0});
    s.spheres.push_back(Sphere{Vec3(0.f), 1.f + 4e-5f, 0});
    s.build();
    Hit h;
    const Ray outside{Vec3(0, 0, 5), Vec3(0, 0, -1)};
    ASSERT_TRUE(s.intersect(outside, h));
    EXPECT_EQ(h.prim, 1u);
    const SurfaceInteraction si = s.interaction(outside, h);
    const Ray in{offsetRayOrigin(si.p, si.pError, si.ng, outside.d), outside.d};  // refracted inwards
    Hit h2;
    ASSERT_TRUE(s.intersect(in, h2, s.skipFor(si, in.d)));
    EXPECT_EQ(h2.prim, 0u);
    EXPECT_NEAR(h2.t, 4e-5f, 1e-6f);
}

// A ray entering a sphere goes straight to the exit only when nothing else reaches into the
// sphere: a plane cutting it, or a second sphere overlapping it, is still met first; a plane or
// sphere that only touches it is not.
TEST(Stability, RayInsideSphereStillMeetsWhatCutsIt) {
    auto firstHit = [](float planeY, bool overlap) {
        Scene s = test::emptyScene();
        s.spheres.push_back(Sphere{Vec3(0.f), 1.f, 0});
        s.spheres.push_back(Sphere{Vec3(overlap ? 1.5f : 2.f, 0.f, 0.f), 1.f, 0});  // 2: touching
        s.planes.push_back(Plane{Vec3(0, 1, 0), -planeY, 0});
        s.build();
        const Ray in{Vec3(0, -5, 0), Vec3(0, 1, 0)};
        Hit h;
        EXPECT_TRUE(s.intersect(in, h, Scene::kNoPrim));
        const SurfaceInteraction si = s.interaction(in, h);
        // Refracted straight on, then turned towards +x, as a ray inside glass would be.
        const Vec3 d = glm::normalize(Vec3(0.8f, 1.f, 0.f));
        const Ray r{offsetRayOrigin(si.p, si.pError, si.ng, d), d};
        Hit h2;
        EXPECT_TRUE(s.intersect(r, h2, s.skipFor(si, d)));
        const bool blocked = s.occluded(r, 100.f, s.skipFor(si, d));
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

// Catalogue 21: the Whitted scene scaled by 1e-4, 1 and 1e5 (camera, lights, geometry, checker)
// renders the same: at least 99.9% of pixels within 1/255.
TEST(Stability, WhittedSceneScaleSweep) {
    DiskFileSource fs;
    const Scene base = loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", fs);
    ASSERT_EQ(base.renderOrigin, DVec3(0.0));
    for (const Light& l : base.lights) ASSERT_EQ(l.attenuation, Vec3(1, 0, 0));  // lighting is scale-free
    auto scaled = [&](float k) {
        Scene s = base;
        s.camera.eye *= k;
        s.camera.target *= k;
        for (Light& l : s.lights) l.position *= k;
        for (Sphere& sp : s.spheres) {
            sp.center *= k;
            sp.radius *= k;
        }
        for (Plane& p : s.planes) p.d *= k;
        for (Material& m : s.materials) m.checkerScale *= k;
        s.build();
        return s;
    };
    const RenderSettings rs = test::smallSettings(96, 54, 1, 5);
    const Image ref = test::render(scaled(1.f), rs);
    for (float k : {1e-4f, 1e5f}) {
        const Image img = test::render(scaled(k), rs);
        EXPECT_LE(test::fractionOff(ref, img, 1), 0.001) << "scale " << k;
    }
}

// Catalogue 22: a scene translated to x = 6.4e6 renders like the untranslated one (the loader
// rebases positions to a render origin chosen from the camera target, in double).
TEST(Stability, SceneFarFromTheOriginRendersTheSame) {
    auto sceneAt = [](double x0) {
        auto v = [&](double x, double y, double z) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "[%.3f, %g, %g]", x0 + x, y, z);
            return std::string(buf);
        };
        return std::string("{") + R"("camera": { "eye": )" + v(0.5, 3, 8) + R"(, "target": )" + v(0, 1, 0) + R"(, "fov": 45 },
          "materials": { "floor": { "checker": { "scale": 2 }, "reflection": 0.2 },
                         "glass": { "transmission": 0.9, "diffuse": 0, "ambient": 0, "ior": 1.5 },
                         "red": { "color": [0.8, 0.1, 0.1], "specular": 0.5 } },
          "lights": [ { "position": )" + v(4, 6, 3) + R"( } ],
          "objects": [ { "type": "plane", "point": )" + v(0, 0, 0) + R"(, "material": "floor" },
                       { "type": "sphere", "center": )" + v(-1.2, 1, 0) + R"(, "radius": 1, "material": "glass" },
                       { "type": "mesh", "material": "red", "positions": [)" + v(0.5, 0, -1) + "," + v(2.5, 0, -1) + "," + v(1.5, 2, -1.5) +
               R"(] } ] })";
    };
    const Scene home = loadText(sceneAt(0.0)), away = loadText(sceneAt(6.4e6));
    EXPECT_EQ(away.renderOrigin.x, 6.4e6);
    const RenderSettings rs = test::smallSettings(96, 64, 1, 5);
    const Image a = test::render(home, rs), b = test::render(away, rs);
    EXPECT_LE(test::fractionOff(a, b, 1), 0.001);
}
