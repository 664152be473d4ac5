// Every texture slot of a glTF material, read through the loader from hand-written files: which
// channel means what (metallicRoughness G/B, occlusion R with strength, normal with scale,
// emissive × factor), that KHR_texture_transform applies to each slot, and, end to end, that an
// emissive texture masks emissiveFactor 1 (the DamagedHelmet case: the model must not glow white)
// and that occlusion dims environment light but not direct light.
#include <gtest/gtest.h>

#include "engine/scene/env_lighting.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/util/image.h"
#include "engine/materials/material_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/integrators/render.h"

using namespace rf;
using namespace gltftest;

namespace {

/// A 20×20 textured floor at y = 0 facing +y (u = (x + 10)/20, v = (z + 10)/20), material 0;
/// images[i] is a 2×1 PNG with texels left[i] | right[i] (RGB bytes), sampled NEAREST.
struct TexturedFloor {
    json materials;
    std::vector<std::array<uint8_t, 3>> left, right;
    json extraNodes = json::array();
};

json floorJson(const TexturedFloor& f, const TempDir& dir) {
    std::string buf;
    put<float>(buf, {-10, 0, -10, -10, 0, 10, 10, 0, 10, 10, 0, -10});
    put<float>(buf, {0, 0, 0, 1, 1, 1, 1, 0});
    put<uint16_t>(buf, {0, 1, 2, 0, 2, 3});
    json images = json::array(), textures = json::array();
    for (size_t i = 0; i < f.left.size(); ++i) {
        const std::vector<uint8_t> px{f.left[i][0], f.left[i][1], f.left[i][2], f.right[i][0], f.right[i][1], f.right[i][2]};
        std::string name = "t";
        name += std::to_string(i);
        name += ".png";
        writePng(dir / name, 2, 1, px);
        images.push_back({{"uri", name}});
        textures.push_back({{"source", i}, {"sampler", 0}});
    }
    json nodes = {{{"mesh", 0}}};
    json roots = {0};
    for (const json& n : f.extraNodes) {
        roots.push_back(nodes.size());
        nodes.push_back(n);
    }
    return json{{"asset", {{"version", "2.0"}}},
                {"extensionsUsed", {"KHR_texture_transform", "KHR_materials_specular", "KHR_lights_punctual"}},
                {"scene", 0},
                {"scenes", {{{"nodes", roots}}}},
                {"nodes", nodes},
                {"materials", f.materials},
                {"images", images},
                {"textures", textures},
                {"samplers", {{{"magFilter", 9728}, {"minFilter", 9728}}}},
                {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
                {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                               {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                               {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
                {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}},
                                 {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
                                 {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}}},
                {"buffers", {{{"uri", dataUri(buf)}, {"byteLength", buf.size()}}}}};
}

Scene loadFloor(const TexturedFloor& f, json patch = json::object()) {
    TempDir dir;
    json g = floorJson(f, dir);
    g.merge_patch(patch);
    writeFile(dir / "m.gltf", g.dump());
    DiskFileSource files;
    return loadGltfScene(dir / "m.gltf", files);
}

/// The material's sample at u (v = 0.5) on the floor.
GltfSample sampleAt(const Scene& s, float u) {
    SurfaceInteraction si;
    si.material = 0;
    si.uv = si.uv1 = Vec2(u, 0.5f);
    return gltfSample(s, si);
}

json shifted(int index, json extra = json::object()) {
    extra["index"] = index;
    extra["extensions"] = {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}};
    return extra;
}

float lin(uint8_t v) { return v / 255.f; }

/// Renders s from 3 above its centre, looking down (a 65×65 image of the middle ±0.77).
Image renderFromAbove(Scene s) {
    s.camera.eye = Vec3(0.f, 3.f, 0.f);
    s.camera.target = Vec3(0.f);
    s.camera.up = Vec3(0.f, 0.f, -1.f);
    s.camera.fovDeg = float(glm::degrees(0.5));
    RenderSettings rs = s.settings;
    rs.spp = 1;  // one ray through each pixel centre, where the hand-computed value holds
    rs.width = rs.height = 65;
    rs.exposure = 0.f;
    rs.autoExposure = false;
    RayStats stats;
    return renderFrame(s, {s.camera, rs}, 0, 1, stats);
}

}  // namespace

TEST(GltfTextureSlots, MetallicRoughnessReadsGreenAndBlueAndItsTransform) {
    TexturedFloor f;
    f.left = {{{255, 64, 191}}};
    f.right = {{{0, 191, 51}}};
    f.materials = {{{"pbrMetallicRoughness", {{"metallicFactor", 0.5}, {"roughnessFactor", 1}, {"metallicRoughnessTexture", {{"index", 0}}}}}}};
    Scene s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.metallic, 0.5f * lin(191), 1e-6);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.roughness, lin(64), 1e-6);
    EXPECT_NEAR(sampleAt(s, 0.75f).surface.metallic, 0.5f * lin(51), 1e-6);
    EXPECT_NEAR(sampleAt(s, 0.75f).surface.roughness, lin(191), 1e-6);
    f.materials[0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = shifted(0);
    s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.roughness, lin(191), 1e-6) << "the transform's offset moves u by half";
}

TEST(GltfTextureSlots, OcclusionReadsRedWithStrengthAndItsTransform) {
    TexturedFloor f;
    f.left = {{{51, 255, 255}}};
    f.right = {{{204, 0, 0}}};
    f.materials = {{{"occlusionTexture", {{"index", 0}, {"strength", 0.5}}}}};
    Scene s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.occlusion, 1.f + 0.5f * (lin(51) - 1.f), 1e-6);
    EXPECT_NEAR(sampleAt(s, 0.75f).surface.occlusion, 1.f + 0.5f * (lin(204) - 1.f), 1e-6);
    f.materials[0]["occlusionTexture"] = shifted(0, {{"strength", 0.5}});
    s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.occlusion, 1.f + 0.5f * (lin(204) - 1.f), 1e-6);
}

TEST(GltfTextureSlots, EmissiveIsFactorTimesSrgbTextureAndItsTransform) {
    TexturedFloor f;
    f.left = {{{0, 0, 0}}};
    f.right = {{{255, 128, 0}}};
    f.materials = {{{"emissiveFactor", {1, 0.5, 1}}, {"emissiveTexture", {{"index", 0}}}}};
    Scene s = loadFloor(f);
    EXPECT_EQ(sampleAt(s, 0.25f).emission, Color(0.f));
    const Color right = sampleAt(s, 0.75f).emission;
    EXPECT_NEAR(right.r, 1.f, 1e-6);
    EXPECT_NEAR(right.g, 0.5f * srgbDecode(128 / 255.f), 1e-6);
    EXPECT_NEAR(right.b, 0.f, 1e-6);
    f.materials[0]["emissiveTexture"] = shifted(0);
    s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).emission.r, 1.f, 1e-6);
}

TEST(GltfTextureSlots, BaseColourIsSrgbTimesFactorAndTakesItsTransform) {
    TexturedFloor f;
    f.left = {{{255, 255, 255}}};
    f.right = {{{128, 0, 64}}};
    f.materials = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1, 1, 1}}, {"baseColorTexture", {{"index", 0}}}}}}};
    Scene s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.baseColor.r, 0.5f, 1e-6);
    EXPECT_NEAR(sampleAt(s, 0.75f).surface.baseColor.r, 0.5f * srgbDecode(128 / 255.f), 1e-6);
    EXPECT_NEAR(sampleAt(s, 0.75f).surface.baseColor.b, srgbDecode(64 / 255.f), 1e-6);
    f.materials[0]["pbrMetallicRoughness"]["baseColorTexture"] = shifted(0);
    s = loadFloor(f);
    EXPECT_NEAR(sampleAt(s, 0.25f).surface.baseColor.g, 0.f, 1e-6);
}

TEST(GltfTextureSlots, NormalTextureTakesItsScaleAndItsTransform) {
    TexturedFloor f;
    f.left = {{{255, 128, 255}}};
    f.right = {{{0, 128, 255}}};
    f.materials = {{{"normalTexture", {{"index", 0}, {"scale", 0.25}}}}};
    Scene s = loadFloor(f);
    const Material& m = s.materials.at(0);
    Vec3 tn = normalTextureSample(s.textures, m, Vec2(0.25f, 0.5f), Vec2(0.25f, 0.5f));
    EXPECT_NEAR(tn.x, 0.25f * 1.f, 1e-6);                   // (2·1 − 1)·scale
    EXPECT_NEAR(tn.y, 0.25f * (2.f * lin(128) - 1.f), 1e-6);
    EXPECT_NEAR(tn.z, 1.f, 1e-6);                           // z is not scaled
    f.materials[0]["normalTexture"] = shifted(0, {{"scale", 0.25}});
    s = loadFloor(f);
    tn = normalTextureSample(s.textures, s.materials.at(0), Vec2(0.25f, 0.5f), Vec2(0.25f, 0.5f));
    EXPECT_NEAR(tn.x, -0.25f, 1e-6);
}

TEST(GltfTextureSlots, EmissiveTextureMasksAnEmissiveFactorOfOne) {
    // DamagedHelmet: emissiveFactor (1, 1, 1) and an emissive texture that is black but for a
    // few lights. No light, no environment: the black half must render black, the lit half
    // the texture's colour, and no pixel white.
    TexturedFloor f;
    f.left = {{{0, 0, 0}}};
    f.right = {{{255, 96, 0}}};
    f.materials = {{{"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}},
                    {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}}}};
    Scene s = loadFloor(f);
    s.lights.clear();
    s.environment.reset();
    const Image img = renderFromAbove(s);
    float brightest = 0.f;
    for (int y = 0; y < 65; ++y)
        for (int x = 0; x < 65; ++x) brightest = std::max(brightest, img.pixel(x, y)[1]);
    EXPECT_NEAR(brightest, srgbDecode(96 / 255.f), 1e-5) << "no pixel brighter than the texture allows";
    for (int c = 0; c < 3; ++c) EXPECT_EQ(img.pixel(8, 32)[c], 0.f) << "the black half glows";
    EXPECT_NEAR(img.pixel(56, 32)[0], 1.f, 1e-5);
    EXPECT_NEAR(img.pixel(56, 32)[1], srgbDecode(96 / 255.f), 1e-5);
}

TEST(GltfTextureSlots, OcclusionDimsTheEnvironmentButNotTheLight) {
    // Left half occlusion 0.25, right half 1. Under a uniform environment alone the left half
    // reads exactly a quarter of the right; under a point light alone both halves agree.
    TexturedFloor f;
    f.left = {{{64, 64, 64}}};
    f.right = {{{255, 255, 255}}};
    f.materials = {{{"occlusionTexture", {{"index", 0}}},
                    {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}}}};
    f.extraNodes = {{{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}};
    Scene s = loadFloor(f, {{"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 683}}}}}}}}});
    ASSERT_EQ(s.lights.size(), 1u);
    Scene envOnly = s;
    envOnly.lights.clear();
    EquirectImage uniform;
    uniform.width = 16;
    uniform.height = 8;
    uniform.texels.assign(16 * 8, Color(1.f));
    envOnly.environment = std::make_shared<const EnvironmentLight>(uniform, 0.f, 1.f, 1);
    const Image env = renderFromAbove(envOnly);
    // Mirror pixels about the centre: same view angle, different halves.
    const float occ = lin(64);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(env.pixel(20, 32)[c], occ * env.pixel(44, 32)[c], 1e-5);
    EXPECT_GT(env.pixel(44, 32)[0], 0.5f);

    s.environment.reset();
    const Image lit = renderFromAbove(s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(lit.pixel(20, 32)[c], lit.pixel(44, 32)[c], 1e-6);
    EXPECT_GT(lit.pixel(44, 32)[0], 0.05f);
}
