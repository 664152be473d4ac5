// The Whitted tracer: the seed's shading formula with attenuation, light types, recursion,
// and the secondary-ray and shading cases 11, 13, 14, 15, 17 and 20 of docs/stability.md.
#include <gtest/gtest.h>

#include <random>

#include "tests/engine/engine_test_util.h"
#include "engine/materials/optics.h"
#include "engine/integrators/whitted.h"

using namespace rf;
using test::matte;

namespace {

/// Plane y = 0 seen straight down at the origin; one light; the material under test.
struct ShadeProbe {
    Scene scene = test::emptyScene();
    SurfaceInteraction si;
    Vec3 dir{0, -1, 0};
    explicit ShadeProbe(const Material& m, const Light& l) {
        scene.materials[0] = m;
        scene.geometry.planes.push_back(Plane{Vec3(0, 1, 0), 0.f, 0});
        scene.lights.push_back(l);
        scene.build();
        Hit h;
        const Ray r{Vec3(0, 5, 0), dir};
        EXPECT_TRUE(scene.geometry.intersect(r, h));
        si = scene.geometry.interaction(r, h);
    }
    Color shade(ShadingModel model = ShadingModel::Phong) {
        RenderSettings s;
        s.shading = model;
        RayStats st;
        return WhittedTracer(scene, s).shade(si, dir, st);
    }
};

Light pointLight(const Vec3& p, const Vec3& att = Vec3(1, 0, 0)) {
    Light l;
    l.position = p;
    l.attenuation = att;
    return l;
}

}  // namespace

// The seed's pruning rule on shadow rays: lights too dim to show are left out, but together they
// never lose more than min_weight at one point. 100 lights worth 5e-4 each (0.05 in all, far above
// 1e-3) must nearly all count; one light worth 5e-4 alone may be dropped.
TEST(Whitted, ShadowPruningBoundsTheTotalLeftOut) {
    Material m = matte(Color(1.f), 0.f, 1.f);
    ShadeProbe p(m, pointLight(Vec3(0, 10, 0)));
    p.scene.lights.clear();
    for (int i = 0; i < 100; ++i) {
        Light l = pointLight(Vec3(0.01f * i, 10.f, 0.f));
        l.intensity = 5e-4f;
        p.scene.lights.push_back(l);
    }
    RenderSettings rs;
    rs.minWeight = 1e-3f;
    RayStats st;
    const Color all = WhittedTracer(p.scene, rs).shade(p.si, p.dir, st);
    float expect = 0.f;
    for (const Light& l : p.scene.lights) expect += l.intensity * glm::normalize(l.position).y;
    EXPECT_GE(all.g, expect - rs.minWeight - 1e-6f);  // 1e-6: float summation order
    EXPECT_LE(all.g, expect + 1e-6f);
    EXPECT_GE(st.shadow, 97u);  // at most two of them left out
    p.scene.lights.resize(1);
    RayStats one;
    const Color single = WhittedTracer(p.scene, rs).shade(p.si, p.dir, one);
    EXPECT_EQ(one.shadow, 0u);
    EXPECT_EQ(single.g, 0.f);
}

// I = I_amb·k_amb + 1/(a + b·d + c·d²)·(k_dif·(N·L) + k_spec·(R·V)^n), as the seed writes it.
TEST(Whitted, SeedPhongFormulaWithAttenuation) {
    Material m = matte(Color(0.6f, 0.4f, 0.2f), 0.1f, 0.9f);
    m.specular = 0.5f;
    m.shininess = 10.f;
    ShadeProbe p(m, pointLight(Vec3(0, 4, 3), Vec3(1.f, 0.1f, 0.01f)));  // d = 5, N·L = 0.8, R·V = 0.8
    const float att = 1.f / (1.f + 0.1f * 5.f + 0.01f * 25.f);
    const Color expect = 0.1f * m.color + att * (0.9f * 0.8f * m.color + Color(0.5f * std::pow(0.8f, 10.f)));
    const Color got = p.shade();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expect[c], 1e-5f);
    // Blinn–Phong: (N·H)^n with H = normalize(L + V) = normalize(0, 1.8, 0.6).
    const float nh = 1.8f / std::sqrt(1.8f * 1.8f + 0.36f);
    const Color blinn = 0.1f * m.color + att * (0.9f * 0.8f * m.color + Color(0.5f * std::pow(nh, 10.f)));
    const Color gotB = p.shade(ShadingModel::BlinnPhong);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(gotB[c], blinn[c], 1e-5f);
}

TEST(Whitted, DirectionalAndSpotLights) {
    Light dir;
    dir.type = LightType::Directional;
    dir.direction = glm::normalize(Vec3(0, -1, -1));  // N·L = cos 45°
    ShadeProbe d(matte(Color(1.f), 0.f, 1.f), dir);
    EXPECT_NEAR(d.shade().g, std::sqrt(0.5f), 1e-6f);

    Light spot = pointLight(Vec3(0, 4, 0));
    spot.type = LightType::Spot;
    spot.direction = Vec3(0, -1, 0);
    spot.innerCone = glm::radians(20.f);
    spot.outerCone = glm::radians(30.f);
    ShadeProbe s(matte(Color(1.f), 0.f, 1.f), spot);
    EXPECT_NEAR(s.shade().r, 1.f, 1e-6f);  // on the axis: full
    // Off the axis, between the cones: x² of the cosine blend; outside the outer cone: dark.
    const Vec3 toP = glm::normalize(Vec3(4.f * std::tan(glm::radians(25.f)), -4.f, 0.f));
    const float c = glm::dot(toP, spot.direction);
    const float x = (c - std::cos(spot.outerCone)) / (std::cos(spot.innerCone) - std::cos(spot.outerCone));
    EXPECT_NEAR(spotFactor(spot, toP), x * x, 1e-6f);
    EXPECT_GT(x, 0.f);
    EXPECT_LT(x, 1.f);
    EXPECT_EQ(spotFactor(spot, glm::normalize(Vec3(4.f * std::tan(glm::radians(35.f)), -4.f, 0.f))), 0.f);
}

// Catalogue 20 (the shading half; the loader half is in scene_loader_test).
TEST(Whitted, AttenuationStaysFiniteAtZeroAndHugeDistance) {
    EXPECT_TRUE(std::isfinite(attenuationFactor(Vec3(0, 0, 1), 0.f)));
    EXPECT_GE(attenuationFactor(Vec3(0, 0, 1), 0.f), 0.f);
    const float far = attenuationFactor(Vec3(0, 0, 1), 1e20f);
    EXPECT_TRUE(std::isfinite(far));
    EXPECT_GE(far, 0.f);
    EXPECT_LT(far, 1e-30f);
    EXPECT_FLOAT_EQ(attenuationFactor(Vec3(1, 0.5f, 0.25f), 2.f), 1.f / 3.f);
    // A light exactly on the surface point: skipped, not NaN.
    ShadeProbe p(matte(Color(1.f)), pointLight(Vec3(0.f), Vec3(0, 0, 1)));
    EXPECT_TRUE(isFinite(p.shade()));
}

TEST(Whitted, MirrorShowsTheBackgroundAndDepthAndPruningLimitRays) {
    // Two facing mirrors (y = 0 and y = 2) with the camera between, looking down at an angle.
    Scene s = test::emptyScene();
    Material mirror = matte(Color(0.f), 0.f, 0.f);
    mirror.reflection = 0.5f;
    s.materials[0] = mirror;
    s.background = Color(0.2f, 0.4f, 0.8f);
    s.geometry.planes.push_back(Plane{Vec3(0, 1, 0), 0.f, 0});
    s.geometry.planes.push_back(Plane{Vec3(0, -1, 0), 2.f, 0});
    s.camera.eye = Vec3(0, 1, 0);
    s.camera.target = Vec3(0, 0, -0.3f);
    s.camera.fovDeg = 10.f;
    s.build();
    RenderSettings rs = test::smallSettings(4, 4, 1, 5);
    rs.minWeight = 0.f;
    RayStats st;
    test::render(s, rs, &st);
    EXPECT_EQ(st.reflection, 16u * 4u);  // depth 5: four generations after the primary ray
    rs.minWeight = 0.1f;                 // weights 0.5, 0.25, 0.125 pass, 0.0625 is pruned
    test::render(s, rs, &st);
    EXPECT_EQ(st.reflection, 16u * 3u);
    // One mirror looking at the sky: exactly the background times the reflectance.
    s.geometry.planes.pop_back();
    s.materials[0].reflection = 1.f;
    s.build();
    const Image img = test::render(s, test::smallSettings(4, 4));
    for (int i = 0; i < 16; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(img.data()[3 * i + c], s.background[c]);
}

TEST(Whitted, GlassOfIndexOneIsInvisible) {
    Scene s = test::emptyScene();
    Material glass = matte(Color(1.f), 0.f, 0.f);
    glass.transmission = 1.f;
    glass.ior = 1.f;
    s.materials[0] = glass;
    s.background = Color(0.3f, 0.5f, 0.7f);
    s.geometry.spheres.push_back(Sphere{Vec3(0.f), 1.f, 0});
    s.camera.eye = Vec3(0, 0, 4);
    s.camera.fovDeg = 40.f;
    s.build();
    RayStats st;
    const Image img = test::render(s, test::smallSettings(24, 24), &st);
    EXPECT_GT(st.refraction, 100u);
    for (int i = 0; i < 24 * 24; ++i)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(img.data()[3 * i + c], s.background[c], 1e-6f) << i;
}

// Catalogue 11: no self-shadowing at range — a floor lit by a light, seen from 1e6 away, and the
// same for a mesh floor scaled by 1e5. Nothing occludes, so shadows on and off must agree.
TEST(Whitted, NoSelfShadowingAtRange) {
    struct Case {
        bool mesh;
        float scale, camDist;
    };
    for (const Case c : {Case{false, 1.f, 1e6f}, Case{true, 1.f, 1e6f}, Case{true, 1e5f, 1e6f * 1e5f / 1e3f}}) {
        Scene s = test::emptyScene();
        s.materials[0] = matte(Color(0.8f), 0.1f, 0.9f);
        if (c.mesh) s.geometry.meshes.push_back(test::gridMesh(6, c.scale));
        else s.geometry.planes.push_back(Plane{Vec3(0, 1, 0), 0.f, 0});
        s.lights.push_back(pointLight(c.scale * Vec3(0.3f, 2.f, 0.2f)));
        const float elev = glm::radians(20.f);
        s.camera.eye = c.camDist * Vec3(0.f, std::sin(elev), std::cos(elev));
        s.camera.fovDeg = glm::degrees(2.f * std::atan(0.8f * c.scale / c.camDist));
        s.build();
        const RenderSettings rs = test::smallSettings(48, 32);
        RayStats st;
        const Image lit = test::render(s, rs, &st);
        s.lights[0].castShadows = false;
        const Image noShadow = test::render(s, rs);
        EXPECT_GT(st.shadow, 48u * 32u / 4u) << "mesh " << c.mesh << " scale " << c.scale;
        size_t differ = 0;
        for (int i = 0; i < 48 * 32 * 3; ++i) differ += lit.data()[i] != noShadow.data()[i];
        EXPECT_EQ(differ, 0u) << "mesh " << c.mesh << " scale " << c.scale;
    }
}

// Catalogue 13: reflected origins lie outside a glass sphere, refracted ones strictly inside
// (and the reverse for rays inside), at several scales and distances from the origin.
TEST(Whitted, SpawnedOriginsLieOnTheRightSide) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (const Sphere sp : {Sphere{Vec3(0.f), 1.f, 0}, Sphere{Vec3(1e4f, -3e3f, 2e2f), 0.5f, 0},
                            Sphere{Vec3(1e-3f, 2e-3f, 0.f), 1e-3f, 0}, Sphere{Vec3(5e5f, 0.f, 0.f), 3e4f, 0}}) {
        Scene s = test::emptyScene();
        s.geometry.spheres.push_back(sp);
        s.build();
        int tested = 0;
        for (int i = 0; i < 4000; ++i) {
            const bool inside = i % 2;
            const Vec3 dirRnd = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
            Ray r;
            r.o = inside ? sp.center + 0.5f * sp.radius * Vec3(u(rng), u(rng), u(rng)) : sp.center - 3.f * sp.radius * dirRnd;
            r.d = inside ? dirRnd : glm::normalize(sp.center + 0.9f * sp.radius * Vec3(u(rng), u(rng), u(rng)) * 0.57f - r.o);
            Hit h;
            if (!s.geometry.intersect(r, h)) continue;
            const SurfaceInteraction si = s.geometry.interaction(r, h);
            Vec3 ng = si.ng;
            const bool entering = glm::dot(r.d, ng) < 0.f;
            if (!entering) ng = -ng;
            const Vec3 refl = reflect(r.d, ng);
            Vec3 refr;
            const float eta = entering ? 1.f / 1.5f : 1.5f;
            const bool hasRefr = refract(r.d, ng, eta, refr);
            auto dist2 = [&](const Vec3& o) {
                const glm::dvec3 f = glm::dvec3(o) - glm::dvec3(sp.center);
                return glm::dot(f, f);
            };
            const double r2 = double(sp.radius) * sp.radius;
            const Vec3 oRefl = offsetRayOrigin(si.p, si.pError, ng, refl);
            EXPECT_TRUE(entering ? dist2(oRefl) > r2 : dist2(oRefl) < r2) << "reflected, case " << i;
            if (hasRefr) {
                const Vec3 oRefr = offsetRayOrigin(si.p, si.pError, ng, refr);
                EXPECT_TRUE(entering ? dist2(oRefr) < r2 : dist2(oRefr) > r2) << "refracted, case " << i;
            }
            ++tested;
        }
        EXPECT_GT(tested, 2000) << sp.radius;
    }
}

// Catalogue 14: a point light 1e-3 above a floor (plane, and mesh) still lights the floor.
TEST(Whitted, LightJustAboveTheFloorStillLightsIt) {
    for (bool mesh : {false, true}) {
        Scene s = test::emptyScene();
        s.materials[0] = matte(Color(0.8f), 0.1f, 0.9f);
        if (mesh) s.geometry.meshes.push_back(test::gridMesh(4, 1.f));
        else s.geometry.planes.push_back(Plane{Vec3(0, 1, 0), 0.f, 0});
        s.lights.push_back(pointLight(Vec3(0.01f, 1e-3f, 0.01f)));
        s.camera.eye = Vec3(0.01f, 1.f, 0.01f);
        s.camera.target = Vec3(0.01f, 0.f, 0.01f);
        s.camera.up = Vec3(0, 0, -1);
        s.camera.fovDeg = 0.001f;  // a few 1e-5 across: every pixel sees N·L ≈ 1
        s.build();
        const Image img = test::render(s, test::smallSettings(3, 3));
        const float expect = 0.1f * 0.8f + 0.9f * 0.8f;
        for (int i = 0; i < 9; ++i) EXPECT_NEAR(img.data()[3 * i], expect, 2e-3f) << "mesh " << mesh << " pixel " << i;
    }
}

// Catalogue 15: a low-poly, smooth-shaded sphere lit from the side. Where the interpolated
// normal faces the light, the faceted neighbours must not cast a shadow (Hanika's terminator
// fix): such pixels receive direct light, as the smooth surface would.
TEST(Whitted, NoShadowTerminatorOnLowPolySmoothMesh) {
    Scene s = test::emptyScene();
    s.materials[0] = matte(Color(1.f), 0.f, 1.f);
    s.geometry.meshes.push_back(test::uvSphere(5, 6, 1.f, Vec3(0.f), true));
    Light l;
    l.type = LightType::Directional;
    l.direction = glm::normalize(Vec3(-1.f, -0.2f, 0.15f));
    s.lights.push_back(l);
    s.camera.eye = Vec3(0.f, 0.f, 4.f);
    s.camera.fovDeg = 35.f;
    s.build();
    const RenderSettings rs = test::smallSettings(96, 96);
    const Image img = test::render(s, rs);
    const CameraRays cam(s.camera, rs.width, rs.height);
    int candidates = 0, behindFacet = 0, dark = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x) {
            const Ray r = cam.generate(x + 0.5f, y + 0.5f);
            Hit h;
            if (!s.geometry.intersect(r, h)) continue;
            const SurfaceInteraction si = s.geometry.interaction(r, h);
            const Vec3 L = -l.direction;
            const float nl = glm::dot(si.ns, L);
            if (nl < 0.02f) continue;  // keep clear of the smooth terminator itself
            ++candidates;
            behindFacet += glm::dot(si.ng, L) <= 0.f;
            // Lit pixels carry k_dif·(N·L); a self-shadowed one would be 0.
            if (img.pixel(x, y)[0] < 0.5f * nl) ++dark;
        }
    EXPECT_GT(candidates, 1000);
    EXPECT_GT(behindFacet, 20);  // the case the fix exists for does occur in this view
    EXPECT_EQ(dark, 0);
}

// Catalogue 17: interpolated normals turned away from the viewer on a visible face fall back on
// the geometric normal: no black contour.
TEST(Whitted, BackFacingShadingNormalFallsBackOnGeometricNormal) {
    Scene s = test::emptyScene();
    s.materials[0] = matte(Color(0.5f), 0.1f, 0.9f);
    TriangleMesh m;
    m.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)};
    const Vec3 away = glm::normalize(Vec3(0.f, 0.8f, -0.6f));  // faces away from a viewer at +z
    m.normals = {away, away, away};
    m.indices = {0, 1, 2};
    s.geometry.meshes.push_back(m);
    Light l;
    l.type = LightType::Directional;
    l.direction = Vec3(0, 0, -1);
    s.lights.push_back(l);
    s.camera.eye = Vec3(0, 0, 3);
    s.camera.target = Vec3(0.f);
    s.camera.fovDeg = 5.f;
    s.build();
    const Image img = test::render(s, test::smallSettings(5, 5));
    const float expect = 0.1f * 0.5f + 0.9f * 0.5f * 1.f;  // with ng = +z: N·L = 1
    for (int i = 0; i < 25; ++i) EXPECT_NEAR(img.data()[3 * i + 1], expect, 1e-5f) << i;
}
