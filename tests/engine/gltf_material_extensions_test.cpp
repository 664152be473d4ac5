// KHR_materials_unlit and KHR_materials_clearcoat against their specifications, on a floor seen
// from above: unlit draws its base colour exactly whatever the light; a clear coat over a black
// base shows the coat's Fresnel alone, (0.04·A + B) of the split sum ≈ Schlick's F(n·v) for a
// smooth coat, under a uniform white environment.
#include <gtest/gtest.h>

#include "brdf_gltf.h"
#include "env_lighting.h"
#include "gltf_loader.h"
#include "gltf_test_util.h"
#include "image.h"
#include "render.h"

using namespace rf;
using namespace gltftest;

namespace {

/// A 20×20 floor at y = 0 facing +y in material 0, a point light 1 above its centre; images:
/// 2×1 PNGs (left | right texels) the materials may use.
Scene loadFloor(const json& material, const std::vector<std::array<uint8_t, 6>>& pngs = {}) {
    TempDir dir;
    std::string buf;
    put<float>(buf, {-10, 0, -10, -10, 0, 10, 10, 0, 10, 10, 0, -10});
    put<float>(buf, {0, 0, 0, 1, 1, 1, 1, 0});
    put<uint16_t>(buf, {0, 1, 2, 0, 2, 3});
    json images = json::array(), textures = json::array();
    for (size_t i = 0; i < pngs.size(); ++i) {
        const std::string name = "t" + std::to_string(i) + ".png";
        writePng(dir / name, 2, 1, std::vector<uint8_t>(pngs[i].begin(), pngs[i].end()));
        images.push_back({{"uri", name}});
        textures.push_back({{"source", i}, {"sampler", 0}});
    }
    json g{{"asset", {{"version", "2.0"}}},
           {"extensionsUsed", {"KHR_materials_unlit", "KHR_materials_clearcoat", "KHR_materials_specular", "KHR_lights_punctual"}},
           {"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 683}}}}}}}},
           {"scene", 0},
           {"scenes", {{{"nodes", {0, 1}}}}},
           {"nodes", {{{"mesh", 0}}, {{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}}},
           {"materials", {material}},
           {"samplers", {{{"magFilter", 9728}, {"minFilter", 9728}}}},
           {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
           {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {-10, 0, -10}}, {"max", {10, 0, 10}}},
                          {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                          {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
           {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
                            {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}}},
           {"buffers", {{{"uri", dataUri(buf)}, {"byteLength", buf.size()}}}}};
    if (!images.empty()) {
        g["images"] = images;
        g["textures"] = textures;
    }
    writeFile(dir / "m.gltf", g.dump());
    DiskFileSource files;
    return loadGltfScene(dir / "m.gltf", files);
}

std::shared_ptr<const EnvironmentLight> uniformEnvironment(float radiance) {
    EquirectImage img;
    img.width = 16;
    img.height = 8;
    img.texels.assign(16 * 8, Color(radiance));
    return std::make_shared<const EnvironmentLight>(img, 0.f, 1.f, 1);
}

/// 65×65 from 3 above the centre looking down (fov 0.5 rad), linear radiance, exposure 0.
Image renderFromAbove(Scene s) {
    s.camera.eye = Vec3(0.f, 3.f, 0.f);
    s.camera.target = Vec3(0.f);
    s.camera.up = Vec3(0.f, 0.f, -1.f);
    s.camera.fovDeg = float(glm::degrees(0.5));
    RenderSettings rs = s.settings;
    rs.spp = 1;
    rs.width = rs.height = 65;
    rs.exposure = 0.f;
    rs.autoExposure = false;
    RayStats stats;
    return renderFrame(s, s.camera, rs, 0, 1, stats);
}

/// n·v at pixel (x, y): the ray through the pixel centre meets the floor's normal +y.
float cosineAt(int x, int y) {
    const float t = std::tan(0.25f);
    const Vec3 d = glm::normalize(Vec3((2.f * (x + 0.5f) / 65.f - 1.f) * t, -1.f, (2.f * (y + 0.5f) / 65.f - 1.f) * t));
    return -d.y;
}

}  // namespace

TEST(GltfMaterialExtensions, UnlitIsTheBaseColourExactly) {
    const json unlit = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.25, 0.5, 0.75, 1}}, {"baseColorTexture", {{"index", 0}}}}},
                        {"extensions", {{"KHR_materials_unlit", json::object()}}}};
    Scene s = loadFloor(unlit, {{{255, 255, 255, 128, 64, 32}}});
    s.environment = uniformEnvironment(3.f);  // light from everywhere and a point light: neither counts
    for (const std::string& n : s.notes) EXPECT_EQ(n.find("KHR_materials_unlit"), std::string::npos) << n;
    const Image img = renderFromAbove(s);
    const Color left(0.25f, 0.5f, 0.75f);
    const Color right = left * Color(srgbDecode(128 / 255.f), srgbDecode(64 / 255.f), srgbDecode(32 / 255.f));
    for (int y = 0; y < 65; ++y)
        for (int x = 0; x < 65; ++x) {
            if (x == 32) continue;  // the texel seam
            const Color want = x < 32 ? left : right;
            for (int c = 0; c < 3; ++c) ASSERT_EQ(img.pixel(x, y)[c], want[c]) << x << "," << y;
        }
    // Control: the same material without the extension is lit (and differs).
    json lit = unlit;
    lit.erase("extensions");
    EXPECT_NE(renderFromAbove(loadFloor(lit, {{{255, 255, 255, 128, 64, 32}}})).pixel(10, 10)[0], left[0]);
}

TEST(GltfMaterialExtensions, ClearcoatOverBlackShowsTheCoatsFresnelAlone) {
    // Black base without a specular layer: nothing but the coat reflects.
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.5}}},
              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}};
    Scene bare = loadFloor(m);
    bare.lights.clear();
    bare.environment = uniformEnvironment(1.f);
    const Image black = renderFromAbove(bare);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(black.pixel(32, 32)[c], 0.f) << "the base reflects";

    m["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.0}};
    Scene coated = loadFloor(m);
    coated.lights.clear();
    coated.environment = uniformEnvironment(1.f);
    const Image img = renderFromAbove(coated);
    double worst = 0.0;
    for (int y = 0; y < 65; y += 4)
        for (int x = 0; x < 65; x += 4) {
            const float nv = cosineAt(x, y);
            const float schlick = 0.04f + 0.96f * std::pow(1.f - nv, 5.f);
            for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(img.pixel(x, y)[c] - schlick)));
        }
    EXPECT_LT(worst, 2e-3) << "a smooth coat under white light reflects Schlick's F(n·v), f0 = 0.04";
    EXPECT_NEAR(img.pixel(32, 32)[0], 0.04f, 2e-3);

    // Half the factor, half the coat; the clearcoat texture's R multiplies it (left 0, right 1).
    m["extensions"]["KHR_materials_clearcoat"] = {{"clearcoatFactor", 0.5}, {"clearcoatTexture", {{"index", 0}}}};
    Scene half = loadFloor(m, {{{0, 0, 0, 255, 255, 255}}});
    half.lights.clear();
    half.environment = uniformEnvironment(1.f);
    const Image h = renderFromAbove(half);
    EXPECT_EQ(h.pixel(20, 32)[0], 0.f);
    EXPECT_NEAR(h.pixel(44, 32)[0], 0.5f * img.pixel(44, 32)[0], 1e-4);
}

TEST(GltfMaterialExtensions, ClearcoatDirectLightIsTheSpecificationsLayering) {
    pbr::Surface s;
    s.baseColor = Color(0.f);
    s.specular = 0.f;
    s.clearcoat = 1.f;
    s.clearcoatRoughness = 0.3f;
    const Vec3 n(0, 0, 1), v = glm::normalize(Vec3(0.3f, 0, 1)), l = glm::normalize(Vec3(-0.4f, 0.1f, 1));
    const Color base = pbr::directLight(s, n, v, l, Color(1.f));
    EXPECT_EQ(base, Color(0.f));
    const Vec3 h = glm::normalize(v + l);
    const float a = 0.09f;
    const float want = pbr::schlickFresnel(0.04f, glm::dot(v, h)) * pbr::ggxD(glm::dot(n, h), a) *
                       pbr::smithVisibility(glm::dot(n, l), glm::dot(n, v), a) * glm::dot(n, l);
    EXPECT_NEAR(pbr::clearcoatDirect(s, n, v, l, base, Color(1.f)).r, want, 2e-5f * want);  // float: two forms of D
    // Over a white diffuse base the coat takes its Fresnel share from it.
    const Color white(0.5f);
    const float fc = pbr::schlickFresnel(0.04f, glm::dot(v, h));
    EXPECT_NEAR(pbr::clearcoatDirect(s, n, v, l, white, Color(1.f)).g, (1.f - fc) * 0.5f + want, 2e-5f * want);
    s.clearcoat = 0.f;
    EXPECT_EQ(pbr::clearcoatDirect(s, n, v, l, white, Color(1.f)), white);
}

TEST(GltfMaterialExtensions, KhronosClearcoatSampleLoadsWithoutNotes) {
    DiskFileSource files;
    const Scene s = loadGltfScene("/usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf", files);
    int coated = 0, coatNormals = 0;
    for (const Material& m : s.materials) coated += m.clearcoat > 0.f, coatNormals += m.clearcoatNormalTexture >= 0;
    EXPECT_GE(coated, 5);
    EXPECT_GE(coatNormals, 1);
    for (const std::string& n : s.notes) EXPECT_EQ(n.find("clearcoat ignored"), std::string::npos) << n;
}

TEST(GltfMaterialExtensions, SpecularGlossinessConvertsAsTheKhronosConverterDoes) {
    DiskFileSource files;
    const Scene s = loadGltfScene("/usr/share/assimp/models/glTF2/BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", files);
    for (const std::string& n : s.notes) EXPECT_EQ(n.find("pbrSpecularGlossiness ignored"), std::string::npos) << n;
    const Material* m = nullptr;
    for (const Material& x : s.materials)
        if (x.name == "Texture") m = &x;
    ASSERT_NE(m, nullptr);
    // diffuse 1, specular 0.2, glossiness 1: by hand, b = 0.8/0.96 + 0.2 - 0.08, c = -0.16,
    // metallic = (-b + sqrt(b^2 - 4*0.04*c)) / 0.08 = 0.1674; both base colour estimates are 1.
    const double b = 0.8 / 0.96 + 0.2 - 0.08, metallic = (-b + std::sqrt(b * b + 4 * 0.04 * 0.16)) / 0.08;
    EXPECT_NEAR(m->metallic, metallic, 1e-5);
    EXPECT_NEAR(m->metallic, 0.1674, 1e-3);
    EXPECT_EQ(m->roughness, 0.f);
    EXPECT_NEAR(m->color.r, 1.f, 1e-5);
    EXPECT_GE(m->baseColorTexture, 0);

    // A plain dielectric (specular 0.04, glossiness 0.25) is metallic 0, base = diffuse, roughness 0.75:
    // exactly the metallic-roughness material it stands for.
    const json sg = {{"extensions", {{"KHR_materials_pbrSpecularGlossiness",
                                      {{"diffuseFactor", {0.5, 0.25, 0.125, 1}}, {"specularFactor", {0.04, 0.04, 0.04}}, {"glossinessFactor", 0.25}}}}}};
    const json mr = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 0.125, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0.75}}}};
    const Scene a = loadFloor(sg), c = loadFloor(mr);
    EXPECT_EQ(a.materials[0].metallic, 0.f);
    EXPECT_NEAR(a.materials[0].roughness, 0.75f, 1e-6);
    const Image ia = renderFromAbove(a), ic = renderFromAbove(c);
    double worst = 0.0;
    for (int y = 0; y < 65; ++y)
        for (int x = 0; x < 65; ++x)
            for (int k = 0; k < 3; ++k) worst = std::max(worst, double(std::abs(ia.pixel(x, y)[k] - ic.pixel(x, y)[k])));
    EXPECT_LT(worst, 1e-5);
}
