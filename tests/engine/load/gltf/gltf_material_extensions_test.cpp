// KHR_materials_unlit and KHR_materials_clearcoat against their specifications, on a floor seen
// from above: unlit draws its base colour exactly whatever the light; a clear coat over a black
// base shows the coat's Fresnel alone, (0.04·A + B) of the split sum ≈ Schlick's F(n·v) for a
// smooth coat, under a uniform white environment.
#include <gtest/gtest.h>

#include "engine/materials/brdf_gltf.h"
#include "tests/engine/gltf_floor_scene.h"
#include "engine/util/image.h"

using namespace rf;
using namespace gltftest;

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

TEST(GltfMaterialExtensions, SpecularGlossinessTexturesAreConvertedTexelByTexel) {
    // A specularGlossinessTexture with a dark left texel and a white right one: each half of the
    // floor renders as the factor-only material with that texel's specular colour, converted on
    // its own (a dielectric on the left, a near-metal on the right). Ignoring the texture, or
    // converting only the factors, draws both halves alike.
    const float gloss = 0.6f;
    auto sg = [&](const json& specular, bool textured) {
        json e = {{"diffuseFactor", {0.7, 0.5, 0.3, 1}}, {"specularFactor", specular}, {"glossinessFactor", gloss}};
        if (textured) e["specularGlossinessTexture"] = {{"index", 0}};
        return json{{"extensions", {{"KHR_materials_pbrSpecularGlossiness", e}}}};
    };
    const std::vector<std::array<uint8_t, 6>> png = {{{40, 40, 40, 255, 255, 255}}};
    const float dark = srgbDecode(40 / 255.f);
    Scene textured = loadFloor(sg({1, 1, 1}, true), png);
    Scene left = loadFloor(sg({dark, dark, dark}, false)), right = loadFloor(sg({1, 1, 1}, false));
    ASSERT_TRUE(textured.materials[0].specularGlossiness);
    ASSERT_GE(textured.materials[0].specularGlossinessTexture, 0);
    EXPECT_EQ(left.materials[0].metallic, 0.f);
    EXPECT_GT(right.materials[0].metallic, 0.5f);
    for (Scene* s : {&textured, &left, &right}) s->environment = uniformEnvironment(0.5f);
    const Image it = renderFromAbove(textured), il = renderFromAbove(left), ir = renderFromAbove(right);
    double worst = 0.0;
    for (int y = 0; y < 65; ++y)
        for (int x = 0; x < 65; ++x) {
            if (x == 32) continue;  // the texel seam
            const Image& want = x < 32 ? il : ir;
            for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(it.pixel(x, y)[c] - want.pixel(x, y)[c])));
        }
    EXPECT_LT(worst, 1e-4);
    EXPECT_GT(std::abs(il.pixel(10, 32)[0] - ir.pixel(10, 32)[0]), 0.05f) << "the two texels must look different";
    for (const std::string& n : textured.notes) EXPECT_EQ(n.find("not converted"), std::string::npos) << n;
}
