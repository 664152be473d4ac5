// glTF materials and KHR_lights_punctual mapped onto the engine, checked against the mapping's
// formulas and, end to end, against a hand-computed pixel of a lit floor.
#include <gtest/gtest.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/gltf/gltf_materials.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/integrators/render.h"

using namespace rf;
using namespace gltftest;

namespace {

/// A 20×20 floor at y = 0 facing +y, drawn with material 0; more nodes may be appended.
json floorModel(json materials, json extraNodes = json::array()) {
    std::string buf;
    put<float>(buf, {-10, 0, -10, -10, 0, 10, 10, 0, 10, 10, 0, -10});
    put<uint16_t>(buf, {0, 1, 2, 0, 2, 3});
    json nodes = {{{"mesh", 0}}};
    json roots = {0};
    for (const json& n : extraNodes) {
        roots.push_back(nodes.size());
        nodes.push_back(n);
    }
    return json{{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", roots}}}},
                {"nodes", nodes},
                {"materials", materials},
                {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}}}},
                {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                               {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
                {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
                {"buffers", {{{"uri", dataUri(buf)}, {"byteLength", buf.size()}}}}};
}

Scene loadScene(const json& g) {
    TempDir dir;
    writeFile(dir / "m.gltf", g.dump());
    DiskFileSource files;
    return loadGltfScene(dir / "m.gltf", files);
}

Material only(const json& material) {
    const Scene s = loadScene(floorModel({material}));
    EXPECT_EQ(s.materials.size(), 1u);
    return s.materials.at(0);
}

}  // namespace

TEST(GltfMaterials, MetallicRoughnessIsShadedByTheGltfBrdf) {
    Material m = only({{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.6, 0.2, 1}}, {"metallicFactor", 1}, {"roughnessFactor", 0}}}});
    EXPECT_TRUE(m.gltfPbr);
    EXPECT_FLOAT_EQ(m.color.g, 0.6f);
    EXPECT_FLOAT_EQ(m.metallic, 1.f);
    EXPECT_FLOAT_EQ(m.roughness, 0.f);
    EXPECT_FLOAT_EQ(m.reflection, 0.f);  // the glTF model traces its own, Fresnel-weighted
    m = only({{"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0.5}}},
              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0.25}}}}}});
    EXPECT_FLOAT_EQ(m.metallic, 0.f);
    EXPECT_FLOAT_EQ(m.roughness, 0.5f);
    EXPECT_FLOAT_EQ(m.specularWeight, 0.25f);
    EXPECT_FLOAT_EQ(gltf::shininessFromRoughness(1.f), 1.f);
}

TEST(GltfMaterials, TransmissionIorEmissionAndAlphaModes) {
    Material m = only({{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}}, {"KHR_materials_ior", {{"ior", 1.33}}}}}});
    EXPECT_FLOAT_EQ(m.transmission, 0.8f);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);

    m = only({{"emissiveFactor", {1, 0.5, 0}}, {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}});
    EXPECT_EQ(m.emission, Color(4.f, 2.f, 0.f));

    m = only({{"alphaMode", "MASK"}, {"alphaCutoff", 0.3}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.2}}}}});
    EXPECT_EQ(m.alphaMode, AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alphaCutoff, 0.3f);
    EXPECT_FLOAT_EQ(m.alpha, 0.2f);

    // BLEND: blended per hit with its alpha (gltfCoverage); nothing turns into transmission.
    m = only({{"alphaMode", "BLEND"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.25}}, {"metallicFactor", 0}}}});
    EXPECT_EQ(m.alphaMode, AlphaMode::Blend);
    EXPECT_FLOAT_EQ(m.alpha, 0.25f);
    EXPECT_FLOAT_EQ(m.transmission, 0.f);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);

    m = only({{"doubleSided", true}});
    EXPECT_TRUE(m.doubleSided);
    m = only(json::object());
    EXPECT_FALSE(m.doubleSided);
}

TEST(GltfMaterials, UnknownMaterialExtensionIsIgnoredWithOneNote) {
    json g = floorModel({{{"extensions", {{"VENDOR_sparkle", {{"amount", 3}}}}}}});
    const Scene s = loadScene(g);
    int notes = 0;
    for (const std::string& n : s.notes) notes += n.find("VENDOR_sparkle") != std::string::npos;
    EXPECT_EQ(notes, 1);
}

TEST(GltfLights, PunctualLightsMapToEngineUnits) {
    const double h = std::sqrt(0.5);
    json g = floorModel({{{"pbrMetallicRoughness", {{"metallicFactor", 0}}}}},
                        {{{"translation", {0, 5, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                         {{"translation", {1, 4, 2}}, {"rotation", {-h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}},
                         {{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}}});
    g["extensionsUsed"] = {"KHR_lights_punctual"};
    g["extensions"] = {{"KHR_lights_punctual",
                        {{"lights",
                          {{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 25 * M_PI}, {"range", 20}},
                           {{"type", "spot"}, {"intensity", 2 * M_PI}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
                           {{"type", "directional"}, {"intensity", M_PI}}}}}}};
    const Scene s = loadScene(g);
    ASSERT_EQ(s.lights.size(), 3u) << "a model with lights gets no default rig";
    const Light& p = s.lights[0];
    EXPECT_EQ(p.type, LightType::Point);
    EXPECT_NEAR(p.intensity, 25.f * kPi / 683.f, 1e-5f);  // candela / 683 lm/W: W/sr
    EXPECT_EQ(p.attenuation, Vec3(0, 0, 1));
    EXPECT_EQ(p.color, Color(1.f, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(p.range, 20.f);
    const glm::dvec3 pw = glm::dvec3(p.position) + s.renderOrigin;
    EXPECT_NEAR(pw.y, 5.0, 1e-6);
    const Light& sp = s.lights[1];
    EXPECT_EQ(sp.type, LightType::Spot);
    EXPECT_NEAR(sp.direction.y, -1.f, 1e-6f);  // −90° about x turns −z into −y
    EXPECT_FLOAT_EQ(sp.innerCone, 0.2f);
    EXPECT_FLOAT_EQ(sp.outerCone, 0.5f);
    EXPECT_EQ(s.lights[2].type, LightType::Directional);
    EXPECT_NEAR(s.lights[2].intensity, kPi / 683.f, 1e-6f);  // lux / 683 lm/W: W/m²
    EXPECT_NEAR(s.lights[2].direction.z, -1.f, 1e-6f);
}

TEST(GltfLights, LitFloorPixelMatchesTheHandComputedValue) {
    // Grey floor (0.5) without a specular layer (KHR_materials_specular 0): Lambertian, 0.5/π.
    // Point light of 25·683 cd (25 W/sr) at 5 above the floor's centre: E = 25/5² = 1 W/m², with
    // the range window (1 − (5/20)⁴)². A glTF camera 10 above looks straight down at the centre.
    const double h = std::sqrt(0.5);
    json g = floorModel({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                          {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}},
                        {{{"translation", {0, 5, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                         {{"translation", {0, 10, 0}}, {"rotation", {-h, 0, 0, h}}, {"camera", 0}}});
    g["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_specular"};
    g["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 25 * 683}, {"range", 20}}}}}}};
    g["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    Scene s = loadScene(g);
    useGltfCamera(s, 0);
    RenderSettings rs = s.settings;
    rs.spp = 1;  // one ray through each pixel centre, where the hand-computed value holds
    rs.width = rs.height = 65;
    RayStats stats;
    const Image img = renderFrame(s, {s.camera, rs}, 0, 1, stats);
    const double window = std::pow(1.0 - std::pow(5.0 / 20.0, 4), 2);
    const double want = 0.5 / M_PI * window;
    EXPECT_NEAR(img.pixel(32, 32)[0], want, 1e-5);
    EXPECT_NEAR(img.pixel(32, 32)[1], want, 1e-5);
}

TEST(GltfLights, A683CandelaLightOneMetreFromWhiteLambertGivesOneOverPi) {
    // The photometric scale at --exposure 0: 683 cd = 1 W/sr; at 1 m, E = 1 W/m², and a white
    // Lambertian surface (no specular layer) sends L = E/π towards the camera.
    const double h = std::sqrt(0.5);
    json g = floorModel({{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                          {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}},
                        {{{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                         {{"translation", {0, 3, 0}}, {"rotation", {-h, 0, 0, h}}, {"camera", 0}}});
    g["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_specular"};
    g["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 683}}}}}}};
    g["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    Scene s = loadScene(g);
    useGltfCamera(s, 0);
    RenderSettings rs = s.settings;
    rs.spp = 1;  // one ray through each pixel centre, where the hand-computed value holds
    rs.width = rs.height = 65;
    rs.exposure = 0.f;
    RayStats stats;
    const Image img = renderFrame(s, {s.camera, rs}, 0, 1, stats);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(img.pixel(32, 32)[c], 1.0 / M_PI, 1e-5);
}

TEST(GltfMaterials, PrimitiveWithoutMaterialGetsAMatteWhiteDefault) {
    json g = floorModel(json::array());
    g.erase("materials");
    g["meshes"][0]["primitives"][0].erase("material");
    const Scene s = loadScene(g);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].color, Color(1.f));
    EXPECT_FLOAT_EQ(s.materials[0].metallic, 0.f);  // read as a dielectric: a rough metal reads as grey plastic anyway
    EXPECT_FLOAT_EQ(s.materials[0].reflection, 0.f);
}

namespace {

/// floorModel with a COLOR_0 accessor (componentType, type "VEC3"/"VEC4", normalized) over the
/// given per-vertex bytes, lit by a 683 cd light 1 above its centre and seen from 3 above
/// (as A683CandelaLight...: a white floor there reads exactly 1/π).
Image renderColouredFloor(int componentType, const std::string& type, bool normalized, const std::string& colourBytes,
                          int stride = 0) {
    const double h = std::sqrt(0.5);
    json g = floorModel({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
                          {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}}},
                        {{{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
                         {{"translation", {0, 3, 0}}, {"rotation", {-h, 0, 0, h}}, {"camera", 0}}});
    g["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_specular"};
    g["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 683}}}}}}};
    g["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    std::string buf;
    put<float>(buf, {-10, 0, -10, -10, 0, 10, 10, 0, 10, 10, 0, -10});
    put<uint16_t>(buf, {0, 1, 2, 0, 2, 3});
    const size_t at = buf.size();
    buf += colourBytes;
    g["buffers"][0] = {{"uri", dataUri(buf)}, {"byteLength", buf.size()}};
    g["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", colourBytes.size()}});
    if (stride) g["bufferViews"][2]["byteStride"] = stride;
    json acc = {{"bufferView", 2}, {"componentType", componentType}, {"count", 4}, {"type", type}};
    if (normalized) acc["normalized"] = true;
    g["accessors"].push_back(acc);
    g["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 2;
    Scene s = loadScene(g);
    useGltfCamera(s, 0);
    RenderSettings rs = s.settings;
    rs.spp = 1;  // one ray through each pixel centre, where the hand-computed value holds
    rs.width = rs.height = 65;
    rs.exposure = 0.f;
    RayStats stats;
    return renderFrame(s, {s.camera, rs}, 0, 1, stats);
}

}  // namespace

TEST(GltfMaterials, VertexColourMultipliesBaseColour) {
    // baseColorFactor (0.5, 1, 1) × COLOR_0 under E = 1 W/m²: L = base × colour / π.
    std::string f;
    for (int i = 0; i < 4; ++i) put<float>(f, {0.8f, 0.5f, 0.25f});
    Image img = renderColouredFloor(5126, "VEC3", false, f);
    EXPECT_NEAR(img.pixel(32, 32)[0], 0.5 * 0.8 / M_PI, 1e-5);
    EXPECT_NEAR(img.pixel(32, 32)[1], 0.5 / M_PI, 1e-5);
    EXPECT_NEAR(img.pixel(32, 32)[2], 0.25 / M_PI, 1e-5);

    // Normalized unsigned bytes, RGBA (alpha does not darken an opaque material).
    std::string b;
    for (int i = 0; i < 4; ++i) put<uint8_t>(b, {255, 51, 102, 128});
    img = renderColouredFloor(5121, "VEC4", true, b);
    EXPECT_NEAR(img.pixel(32, 32)[0], 0.5 / M_PI, 1e-5);
    EXPECT_NEAR(img.pixel(32, 32)[1], 0.2 / M_PI, 1e-5);
    EXPECT_NEAR(img.pixel(32, 32)[2], 0.4 / M_PI, 1e-5);

    // Normalized unsigned shorts, RGB (vertex attributes align to 4 bytes: a stride of 8).
    std::string u;
    for (int i = 0; i < 4; ++i) put<uint16_t>(u, {0, 65535, 13107, 0});
    img = renderColouredFloor(5123, "VEC3", true, u, 8);
    EXPECT_NEAR(img.pixel(32, 32)[0], 0.0, 1e-6);
    EXPECT_NEAR(img.pixel(32, 32)[1], 1.0 / M_PI, 1e-5);
    EXPECT_NEAR(img.pixel(32, 32)[2], 0.2 / M_PI, 1e-5);
}

TEST(GltfMaterials, VertexColourIsInterpolatedAcrossTheTriangle) {
    // Red at vertex 0, blue at vertex 2 (the quad's diagonal runs between them through the
    // centre), green at 1 and 3: the centre is half red, half blue. Base colour factor 0.5 in red.
    std::string f;
    put<float>(f, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0});
    const Image img = renderColouredFloor(5126, "VEC3", false, f);
    EXPECT_NEAR(img.pixel(32, 32)[0], 0.5 * 0.5 / M_PI, 2e-3);
    EXPECT_NEAR(img.pixel(32, 32)[1], 0.0, 2e-3);
    EXPECT_NEAR(img.pixel(32, 32)[2], 0.5 / M_PI, 2e-3);
    // Off the diagonal, towards vertex 1 (−10, 0, 10): green shows.
    float greenLeft = 0.f;
    for (int x = 0; x < 65; ++x) greenLeft = std::max(greenLeft, img.pixel(x, 64)[1] + img.pixel(x, 0)[1]);
    EXPECT_GT(greenLeft, 2e-3f);
}

TEST(GltfMaterials, VertexColourOfAnIntegerTypeThatIsNotNormalizedIsRefused) {
    std::string b;
    for (int i = 0; i < 4; ++i) put<uint8_t>(b, {255, 51, 102, 128});
    try {
        renderColouredFloor(5121, "VEC4", false, b);
        ADD_FAILURE() << "a non-normalized unsigned byte COLOR_0 loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("COLOR_0"), std::string::npos) << e.what();
    }
}
