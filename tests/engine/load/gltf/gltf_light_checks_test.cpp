// Issue 46 #6: glTF lights and IORs out of range are refused naming the light or material and
// the value (InputError, exit 2), as a scene file's are, instead of rendering black silently.
#include <gtest/gtest.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
using namespace gltftest;

namespace {

float kA[3] = {0, 0, 0}, kB[3] = {1, 0, 0}, kC[3] = {0, 1, 0};

/// The one-triangle model lit by `light` (a KHR_lights_punctual light on a second node) or with
/// `material` as its material; the error message of its load, "" when it loads.
std::string loadWith(const json& light, const json& material = nullptr) {
    json doc = oneTriangleGltf("tri.bin");
    if (!light.is_null()) {
        doc["nodes"].push_back({{"translation", {0, 0, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
        doc["scenes"][0]["nodes"].push_back(doc["nodes"].size() - 1);
        doc["extensionsUsed"] = {"KHR_lights_punctual"};
        doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {light}}}}};
    }
    if (!material.is_null()) {
        doc["materials"] = {material};
        doc["meshes"][0]["primitives"][0]["material"] = 0;
        doc["extensionsUsed"] = {"KHR_materials_ior"};
    }
    TempDir dir;
    writeFile(dir / "tri.bin", oneTriangleBytes(kA, kB, kC));
    writeFile(dir / "model.gltf", doc.dump());
    DiskFileSource files;
    Scene scene;
    try {
        loadGltfModel(scene, dir / "model.gltf", DMat4(1.0), files);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

void expectRefused(const json& light, const std::string& message) {
    const std::string e = loadWith(light);
    EXPECT_NE(e.find("model.gltf: " + message), std::string::npos) << "got: \"" << e << "\"";
}

}  // namespace

TEST(GltfLightChecks, ValuesASceneFileRefusesAreRefused) {
    expectRefused({{"type", "point"}, {"name", "Lamp"}, {"intensity", -5}},
                  "KHR_lights_punctual.lights[0] (\"Lamp\").intensity -5: expected a number ≥ 0");
    expectRefused({{"type", "point"}, {"color", {1, -0.5, 1}}},
                  "KHR_lights_punctual.lights[0].color [1, -0.5, 1]: colour components must be ≥ 0");
    expectRefused({{"type", "point"}, {"range", 0}},
                  "KHR_lights_punctual.lights[0].range 0: expected a positive distance (leave range out for no limit)");
    expectRefused({{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.3}}}},
                  "KHR_lights_punctual.lights[0].spot.innerConeAngle 0.6: must not exceed outerConeAngle 0.3");
    expectRefused({{"type", "spot"}, {"spot", {{"innerConeAngle", -0.1}}}},
                  "KHR_lights_punctual.lights[0].spot.innerConeAngle -0.1: expected radians ≥ 0");
}

TEST(GltfLightChecks, ValidLightsStillLoad) {
    EXPECT_EQ(loadWith({{"type", "point"}, {"intensity", 0}}), "");  // off, but allowed
    EXPECT_EQ(loadWith({{"type", "point"}, {"range", 5}, {"color", {0, 0, 0}}}), "");
    EXPECT_EQ(loadWith({{"type", "spot"}, {"spot", {{"innerConeAngle", 0.3}, {"outerConeAngle", 0.3}}}}), "");
    EXPECT_EQ(loadWith({{"type", "directional"}}), "");  // range absent: no limit
}

TEST(GltfLightChecks, IorBelowOneIsRefusedNamingTheMaterial) {
    const std::string e = loadWith(nullptr, {{"name", "Glass"}, {"extensions", {{"KHR_materials_ior", {{"ior", -1.5}}}}}});
    EXPECT_NE(e.find("model.gltf: materials[0] (\"Glass\").extensions.KHR_materials_ior.ior -1.5: expected an index of refraction of 1 or "
                     "more (or 0)"),
              std::string::npos)
        << e;
    EXPECT_NE(loadWith(nullptr, {{"extensions", {{"KHR_materials_ior", {{"ior", 0.5}}}}}}).find("ior 0.5"), std::string::npos);
    EXPECT_EQ(loadWith(nullptr, {{"extensions", {{"KHR_materials_ior", {{"ior", 0}}}}}}), "");  // the schema's special value
    EXPECT_EQ(loadWith(nullptr, {{"extensions", {{"KHR_materials_ior", {{"ior", 2.4}}}}}}), "");
}
