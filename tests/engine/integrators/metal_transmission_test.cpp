// KHR_materials_transmission as glTF mixes it: mix(dielectric, metal, metallic), and only the
// dielectric transmits (material_gltf.h, gltfTransmission). A sphere of transmission 1 and
// metallic 1 (glTF's default metallic) is opaque metal: no refracted rays, no light through it
// to its shadow; at metallic 0.5 half the transmission is left; at metallic 0 all of it.
#include <gtest/gtest.h>

#include "tests/engine/engine_test_util.h"
#include "engine/integrators/light_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/integrators/shading_frame.h"
#include "engine/integrators/render.h"

using namespace rf;

namespace {

Scene sphereOverFloor(float metallic) {
    Scene s;
    Material floor = test::matte(Color(0.8f), 0.1f, 0.9f);
    Material ball;
    ball.gltfPbr = true;
    ball.color = Color(1.f);
    ball.metallic = metallic;
    ball.roughness = 0.3f;
    ball.transmission = 1.f;
    ball.ior = 1.5f;
    s.materials = {floor, ball};
    s.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    s.geometry.spheres.push_back({Vec3(0.f, 1.f, 0.f), 1.f, 1});
    Light l;
    l.position = Vec3(0.f, 6.f, 0.f);  // straight above: the ball's shadow lies under it
    s.lights = {l};
    s.background = Color(0.3f, 0.35f, 0.4f);
    s.camera.eye = Vec3(0.f, 3.f, 4.f);
    s.camera.target = Vec3(0.f, 0.7f, 0.f);
    s.camera.fovDeg = 40.f;
    s.build();
    return s;
}

/// What gltfTransmission says at the ball's top.
float transmissionAtTop(const Scene& s) {
    Ray r;
    r.o = Vec3(0.f, 5.f, 0.f);
    r.d = Vec3(0.f, -1.f, 0.f);
    Hit hit;
    EXPECT_TRUE(s.geometry.intersect(r, hit));
    const SurfaceInteraction si = s.geometry.interaction(r, hit);
    EXPECT_EQ(gltfSample(s, si).transmission, gltfTransmission(s, si));
    return gltfTransmission(s, si);
}

}  // namespace

TEST(MetalTransmission, OnlyTheDielectricPartTransmits) {
    EXPECT_EQ(transmissionAtTop(sphereOverFloor(1.f)), 0.f);
    EXPECT_EQ(transmissionAtTop(sphereOverFloor(0.5f)), 0.5f);
    EXPECT_EQ(transmissionAtTop(sphereOverFloor(0.f)), 1.f);  // glass as it was, to the bit
}

TEST(MetalTransmission, TransmissionOnAMetalIsOpaqueMetal) {
    const RenderSettings rs = test::smallSettings(48, 32);
    RayStats metal, half, glass;
    test::render(sphereOverFloor(1.f), rs, &metal);
    test::render(sphereOverFloor(0.5f), rs, &half);
    test::render(sphereOverFloor(0.f), rs, &glass);
    EXPECT_EQ(metal.refraction, 0u) << "a metal refracts nothing";
    EXPECT_GT(half.refraction, 0u);
    EXPECT_GT(glass.refraction, 0u);
    // Its shadow is a metal's: no light through it onto the floor below.
    for (float metallic : {1.f, 0.f}) {
        const Scene s = sphereOverFloor(metallic);
        Ray r;
        r.o = Vec3(3.f, 0.5f, 0.3f);  // low over the floor, past the ball, to a spot in its shadow
        r.d = glm::normalize(Vec3(0.3f, 0.f, 0.3f) - r.o);
        Hit hit;
        ASSERT_TRUE(s.geometry.intersect(r, hit));
        const SurfaceInteraction si = s.geometry.interaction(r, hit);
        ASSERT_EQ(si.material, 0);
        const ShadingFrame frame = shadingFrame(s, si, -r.d);
        ShadowRays shadows(s, si, frame, nullptr);
        LightIncidence li;
        ASSERT_TRUE(lightIncidence(s.lights[0], si.p, frame.ns, li));
        RayStats st;
        const Color t = shadows.transmittance(s.lights[0], li, false, st, true);
        if (metallic > 0.f) EXPECT_EQ(t, Color(0.f));
        else EXPECT_GT(t.g, 0.5f);
    }
}
