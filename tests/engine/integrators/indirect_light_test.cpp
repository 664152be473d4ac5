// Sampled indirect light (RenderSettings::indirectSamples): its sample sets, that an open
// surface keeps the default's noise-free value exactly, that a floor's bounce lights the
// underside of a sphere the default leaves black and that a sphere occludes the environment
// on the floor beside it, and that a frame is the same on any thread count and tile split.
#include <gtest/gtest.h>

#include "tests/engine/engine_test_util.h"
#include "engine/scene/env_lighting.h"
#include "engine/materials/hemisphere.h"

namespace rf {
namespace {

/// A rough white glTF floor (2×2 at y = 0) and, when sphereY > 0, a red glTF sphere of radius
/// 0.3 centred sphereY above it; a sun at 45° (from +x) and/or a uniform environment of 0.5;
/// seen from the side and a little above.
Scene floorScene(float sphereY, bool sun, bool environment) {
    Scene s = test::emptyScene();
    Material& floor = s.materials[0];
    floor.gltfPbr = true;
    floor.color = Color(0.8f);
    floor.metallic = 0.f;
    floor.roughness = 1.f;
    s.geometry.meshes.push_back(test::gridMesh(8, 1.f, 0));
    if (sphereY > 0.f) {
        Material ball = floor;
        ball.color = Color(0.8f, 0.2f, 0.2f);
        s.materials.push_back(ball);
        s.geometry.meshes.push_back(test::uvSphere(24, 48, 0.3f, Vec3(0.f, sphereY, 0.f), true, 1));
    }
    if (sun) {
        Light l;
        l.type = LightType::Directional;
        l.direction = glm::normalize(Vec3(-1.f, -1.f, 0.f));
        l.intensity = 2.f;
        s.lights.push_back(l);
    }
    if (environment) {
        EquirectImage grey;
        grey.width = 16;
        grey.height = 8;
        grey.texels.assign(16 * 8, Color(0.5f));
        s.environment = std::make_shared<const EnvironmentLight>(grey, 0.f, 1.f, 1);
    }
    s.camera.eye = Vec3(0.f, 0.25f, 1.6f);
    s.camera.target = Vec3(0.f, 0.2f, 0.f);
    s.camera.fovDeg = 50.f;
    s.build();
    return s;
}

void writeOnFailure(const Image& plain, const Image& sampled, const std::string& name) {
    if (!::testing::Test::HasFailure()) return;
    writePng(std::string(RAYFARM_TEST_OUT) + "/" + name + "_default.png", 64, 48, toRgb8(plain, ToneMap::Clamp));
    writePng(std::string(RAYFARM_TEST_OUT) + "/" + name + "_indirect.png", 64, 48, toRgb8(sampled, ToneMap::Clamp));
}

Image renderWith(const Scene& s, int indirect, int threads = 1, int tile = 32, int bounce = 0) {
    RenderSettings rs = test::smallSettings(64, 48);
    rs.indirectSamples = indirect;
    rs.bounce = bounce;  // the bounce cache (bounce_cache_test.cpp) off unless asked for
    rs.tileSize = tile;
    return test::render(s, rs, nullptr, threads);
}

}  // namespace

TEST(IndirectLight, SampleSetsAreStratifiedAndCosineDistributed) {
    const uint32_t n = 256;
    double meanZ = 0.0;
    int lowerLeft = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const Vec2 u = stratifiedPoint(i, n, Vec2(0.37f, 0.81f));
        ASSERT_TRUE(u.x >= 0.f && u.x < 1.f && u.y >= 0.f && u.y < 1.f);
        lowerLeft += u.x < 0.5f && u.y < 0.5f;
        const Vec3 d = cosineHemisphere(u);
        EXPECT_NEAR(glm::length(d), 1.f, 1e-5f);
        EXPECT_GE(d.z, 0.f);
        meanZ += d.z / n;
    }
    EXPECT_EQ(lowerLeft, int(n / 4));     // a quarter of a (0, m, 2)-net in each quadrant
    EXPECT_NEAR(meanZ, 2.0 / 3.0, 0.01);  // E[cos θ] under cos θ/π
}

TEST(IndirectLight, AnOpenSurfaceKeepsTheDefaultExactly) {
    // Nothing above the floor: every sample escapes, the ratio is 1, and the picture is the
    // split sum's, bit for bit (no noise where nothing is in the way).
    const Scene s = floorScene(0.f, true, true);
    const Image a = renderWith(s, 0), b = renderWith(s, 16);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) ASSERT_EQ(a.pixel(x, y)[c], b.pixel(x, y)[c]) << x << "," << y;
}

TEST(IndirectLight, TheFloorsBounceLightsTheUndersideOfASphereDirectLightLeavesBlack) {
    // pbr_grid's lights-only case: a sphere above a sunlit floor, no environment. Its underside
    // faces away from the sun: black with direct light alone (--bounce 0); sampled, the lit
    // floor below lights it, and so does the default look's bounce cache.
    const Scene s = floorScene(0.5f, true, false);
    const Image plain = renderWith(s, 0), sampled = renderWith(s, 16);
    const Image cached = renderWith(s, 0, 1, 32, kDefaultBounce);
    for (int y = 21; y < 24; ++y)
        for (int x = 30; x < 35; ++x) {
            EXPECT_EQ(plain.pixel(x, y)[0], 0.f) << x << "," << y;
            EXPECT_GT(sampled.pixel(x, y)[0], 0.02f) << x << "," << y;
            EXPECT_GT(cached.pixel(x, y)[0], 0.02f) << x << "," << y;
        }
    writeOnFailure(plain, sampled, "indirect_bounce");
    writeOnFailure(plain, cached, "indirect_bounce_cached");
}

TEST(IndirectLight, ASphereOccludesTheEnvironmentOnTheFloorBesideIt) {
    // Environment light only, a sphere resting on the floor: the floor just in front of its
    // contact sees less sky; the default lights it as if the sphere were not there.
    const Scene s = floorScene(0.3f, false, true);
    const Image plain = renderWith(s, 0), sampled = renderWith(s, 16);
    float plainFloor = 0.f, sampledFloor = 0.f;
    for (int y = 31; y < 34; ++y)
        for (int x = 26; x < 38; ++x) {
            plainFloor += plain.pixel(x, y)[1];
            sampledFloor += sampled.pixel(x, y)[1];
        }
    EXPECT_LT(sampledFloor, 0.9f * plainFloor) << "no occlusion of the environment beside the sphere";
    writeOnFailure(plain, sampled, "indirect_occlusion");
}

TEST(IndirectLight, AFrameIsTheSameOnAnyThreadCountAndTileSplit) {
    const Scene s = floorScene(0.3f, true, true);
    const Image a = renderWith(s, 8, 1, 32), b = renderWith(s, 8, 2, 7);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) ASSERT_EQ(a.pixel(x, y)[c], b.pixel(x, y)[c]) << x << "," << y;
}

}  // namespace rf
