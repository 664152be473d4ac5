// JSON scene files: what they load into, and errors that name the file and the JSON path
// ("x.json: lights[2].color: expected 3 numbers"), including catalogue 20's load-time check.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "engine/util/errors.h"
#include "engine/geometry/render_origin.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {

LoadedScene loadText(const std::string& text, const std::string& name = "x.json") {
    FileBundle b;
    b.files[name] = text;
    BundleFileSource fs(b);
    return loadScene(name, fs);
}

/// The message of the InputError that loading `text` throws ("" if none).
std::string errorOf(const std::string& text) {
    try {
        loadText(text);
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "x.json");
        return e.what();
    }
    return "";
}

const char* kGood = R"({
  "camera": { "eye": [0, 2, 8], "target": [0, 1, 0], "fov": 40, "fov_axis": "horizontal", "handedness": "left" },
  "background": [0.1, 0.2, 0.3],
  "render": { "width": 64, "height": 48, "spp": 4, "max_depth": 3, "tonemap": "reinhard", "shading": "blinn-phong" },
  "materials": { "red": { "color": [1, 0, 0], "specular": 0.5, "shininess": 20 },
                 "glass": { "transmission": 0.9, "ior": 1.33 } },
  "lights": [ { "type": "point", "position": [1, 5, 2], "attenuation": [1, 0.1, 0.01] },
              { "type": "directional", "direction": [0, -2, 0], "color": [0.5, 0.5, 0.5] },
              { "type": "spot", "position": [0, 4, 0], "direction": [0, -1, 0], "inner_angle": 10, "outer_angle": 20 } ],
  "objects": [ { "type": "sphere", "center": [0, 1, 0], "radius": 1, "material": "red" },
               { "type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0] },
               { "type": "mesh", "positions": [[0,0,0],[1,0,0],[0,1,0],[1,1,0]], "indices": [0,1,2, 1,3,2],
                 "normals": [[0,0,1],[0,0,1],[0,0,1],[0,0,1]], "material": "glass" },
               { "type": "triangle", "vertices": [[0,0,1],[1,0,1],[0,1,1]] } ]
})";

}  // namespace

TEST(SceneLoader, LoadsEverySection) {
    const LoadedScene sLoaded = loadText(kGood);
    const Scene& s = sLoaded.scene;
    EXPECT_EQ(s.settings.width, 64);
    EXPECT_EQ(s.settings.spp, 4);
    EXPECT_EQ(s.settings.maxDepth, 3);
    EXPECT_EQ(s.settings.toneMap, ToneMap::Reinhard);
    EXPECT_EQ(s.settings.shading, ShadingModel::BlinnPhong);
    EXPECT_TRUE(s.camera.fovHorizontal);
    EXPECT_TRUE(s.camera.leftHanded);
    EXPECT_FLOAT_EQ(s.camera.fovDeg, 40.f);
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[1].type, LightType::Directional);
    EXPECT_NEAR(s.lights[1].direction.y, -1.f, 1e-6f);  // normalised
    EXPECT_EQ(s.lights[2].type, LightType::Spot);
    EXPECT_NEAR(s.lights[2].outerCone, glm::radians(20.f), 1e-6f);
    EXPECT_EQ(s.lights[0].attenuation, Vec3(1.f, 0.1f, 0.01f));
    ASSERT_EQ(s.materials.size(), 3u);  // default + red + glass
    EXPECT_EQ(s.geometry.spheres.size(), 1u);
    EXPECT_EQ(s.geometry.planes.size(), 1u);
    ASSERT_EQ(s.geometry.meshes.size(), 2u);
    EXPECT_EQ(s.geometry.meshes[0].triangleCount(), 2u);
    EXPECT_EQ(s.geometry.meshes[0].normals.size(), 4u);
    EXPECT_FLOAT_EQ(s.materials[s.geometry.meshes[0].material].ior, 1.33f);
    EXPECT_EQ(s.geometry.triangleCount(), 3u);
    EXPECT_EQ(s.sourcePath, "x.json");
}

TEST(SceneLoader, ErrorsNameTheFileAndTheJsonPath) {
    EXPECT_EQ(errorOf(R"({"lights": [{"position": [0,1,0]}, {"position": [0,1,0]}, {"position": [0,1,0], "color": [1, 2]}]})"),
              "x.json: lights[2].color: expected 3 numbers");
    EXPECT_EQ(errorOf(R"({"render": {"width": "big"}})"), "x.json: render.width: expected an integer");
    EXPECT_EQ(errorOf(R"({"render": {"width": 0}})"), "x.json: render.width: expected an integer from 1 to 16384");
    EXPECT_EQ(errorOf(R"({"camera": {"fob": 3}})"), "x.json: camera.fob: unknown key");
    EXPECT_EQ(errorOf(R"({"cameras": {}})"), "x.json: cameras: unknown key");
    EXPECT_EQ(errorOf(R"([1, 2])"), "x.json: expected an object");
    EXPECT_EQ(errorOf(R"({"objects": [{"type": "sphere", "radius": -1}]})"),
              "x.json: objects[0].radius: expected a positive number");
    EXPECT_EQ(errorOf(R"({"objects": [{"type": "sphere", "material": "gold"}]})"),
              "x.json: objects[0].material: no material named \"gold\"");
    EXPECT_EQ(errorOf(R"({"objects": [{"type": "cube"}]})"),
              "x.json: objects[0].type: expected \"sphere\", \"plane\", \"triangle\", \"mesh\" or \"model\"");
    EXPECT_EQ(errorOf(R"({"objects": [{"type": "mesh", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [0, 1, 3]}]})"),
              "x.json: objects[0].indices[2]: expected an index below 3");
    EXPECT_EQ(errorOf(R"({"materials": {"m": {"diffuse": true}}})"), "x.json: materials.m.diffuse: expected a number");
    EXPECT_EQ(errorOf(R"({"camera": {"eye": [1, 2, 3], "target": [1, 2, 3]}})"),
              "x.json: camera.target: eye and target coincide, so the view direction is undefined");
    EXPECT_EQ(errorOf(R"({"camera": {"handedness": "up"}})"), "x.json: camera.handedness: expected \"right\" or \"left\"");
    EXPECT_EQ(errorOf(R"({"render": {"spp": 5}})"), "x.json: render.spp: expected a square number of samples (1, 4, 9, 16, ...)");
    EXPECT_EQ(errorOf(R"({"lights": [{"type": "spot", "position": [0, 1, 0]}]})"), "x.json: lights[0]: a spot light needs a direction");
    EXPECT_EQ(errorOf(R"({"lights": [{"type": "directional", "direction": [0, 0, 0]}]})"),
              "x.json: lights[0].direction: expected a non-zero direction");
}

TEST(SceneLoader, BadJsonNamesTheFile) {
    const std::string msg = errorOf(R"({"camera": {"eye": [0, 1, 2],}})");
    EXPECT_EQ(msg.rfind("x.json: not valid JSON", 0), 0u) << msg;
    // A number beyond double's range is refused as input, not thrown past the loader.
    const std::string big = errorOf(R"({"materials": {"m": {"ior": 1e400}}})");
    EXPECT_EQ(big.rfind("x.json: not valid JSON", 0), 0u) << big;
}

// Catalogue 20: a = b = c = 0 would make 1/(a + b·d + c·d²) infinite: rejected at load time.
TEST(SceneLoader, RejectsAllZeroAttenuation) {
    const std::string msg = errorOf(R"({"lights": [{"position": [0, 1, 0], "attenuation": [0, 0, 0]}]})");
    EXPECT_EQ(msg.rfind("x.json: lights[0].attenuation: ", 0), 0u) << msg;
    EXPECT_EQ(errorOf(R"({"lights": [{"position": [0, 1, 0], "attenuation": [1, -1, 0]}]})"),
              "x.json: lights[0].attenuation: coefficients must be ≥ 0");
    EXPECT_EQ(errorOf(R"({"lights": [{"position": [0, 1, 0], "attenuation": [0, 0, 1]}]})"), "");
}

TEST(SceneLoader, MissingFileAndUnknownExtension) {
    FileBundle empty;
    BundleFileSource fs(empty);
    try {
        loadScene("nowhere.json", fs);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "nowhere.json");
    }
    try {
        loadScene("scene.xyz", fs);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "scene.xyz: unknown scene type (expected .json, .gltf or .glb, or a model in .obj, .stl, .ply, .fbx, .dae and .3mf)");
    }
    // A format assimp reads but rayfarm does not vouch for: refused, naming those it reads.
    try {
        loadScene("ship.3ds", fs);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "ship.3ds: rayfarm does not read .3ds files (assimp could, but rayfarm is not tested on them); it reads .json "
                  "scene files, glTF (.gltf, .glb) and through assimp .obj, .stl, .ply, .fbx, .dae and .3mf");
    }
    // A vouched format that is not there: the file source's own message.
    try {
        loadScene("scene.obj", fs);
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "scene.obj");
    }
}

// Catalogue 22 (loader half): positions are rebased to a render origin near the camera target,
// in double, so a model at x = 6.4e6 arrives with small, exact render-space coordinates.
TEST(SceneLoader, RebasesFarScenesToARenderOrigin) {
    const LoadedScene sLoaded = loadText(R"({
      "camera": { "eye": [6400000, 3, -8], "target": [6400000, 1, 0] },
      "lights": [ { "position": [6400010.5, 12, -6] } ],
      "objects": [ { "type": "sphere", "center": [6400002.8, 1, -2.2], "radius": 1 },
                   { "type": "plane", "normal": [0, 1, 0], "point": [6400000, 0, 0] } ] })");
    const Scene& s = sLoaded.scene;
    EXPECT_EQ(s.renderOrigin, DVec3(6400000.0, 0.0, 0.0));
    EXPECT_EQ(s.geometry.spheres[0].center, Vec3(2.8f, 1.f, -2.2f));
    EXPECT_EQ(s.lights[0].position, Vec3(10.5f, 12.f, -6.f));
    EXPECT_EQ(s.camera.eye, Vec3(0.f, 3.f, -8.f));
    EXPECT_EQ(s.geometry.planes[0].d, 0.f);
    EXPECT_EQ(chooseRenderOrigin(DVec3(100.0, -31.0, 33.0)), DVec3(128.0, -0.0, 64.0));
}

TEST(SceneLoader, ShippedScenesLoad) {
    for (const char* name : {"whitted.json", "spot_lights.json", "glass_tir.json", "mesh_phong.json"}) {
        DiskFileSource fs;
        const std::string path = std::string(RAYFARM_SOURCE_DIR) + "/scenes/" + name;
        EXPECT_NO_THROW(loadScene(path, fs)) << path;
    }
}

// A model's "material" puts every primitive of it in the scene's own material (a clay render).
TEST(SceneLoader, ModelMaterialOverridesTheFilesMaterials) {
    std::ifstream in(std::string(RAYFARM_SOURCE_DIR) + "/scenes/model_on_floor.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key = "\"type\": \"model\", ";
    ASSERT_NE(text.find(key), std::string::npos);
    const std::string dir = ::testing::TempDir();
    auto loadWith = [&](const std::string& extra, const std::string& name) {
        std::string t = text;
        t.replace(t.find(key), key.size(), key + extra);
        const std::string path = dir + "/" + name;
        std::ofstream(path) << t;
        DiskFileSource fs;
        return loadScene(path, fs).scene;
    };
    const Scene own = loadWith("", "own.json");
    const Scene clay = loadWith("\"material\": \"floor\", ", "clay.json");
    ASSERT_EQ(own.geometry.meshes.size(), clay.geometry.meshes.size());
    ASSERT_FALSE(clay.geometry.meshes.empty());
    // The file's materials and textures are not read: BoxTextured's image stays undecoded.
    EXPECT_FALSE(own.textures.empty());
    EXPECT_TRUE(clay.textures.empty());
    EXPECT_EQ(clay.materials.size(), 2u);  // default + floor
    for (size_t i = 0; i < own.geometry.meshes.size(); ++i) {
        EXPECT_TRUE(own.materials[size_t(own.geometry.meshes[i].material)].gltfPbr) << i;
        const Material& m = clay.materials[size_t(clay.geometry.meshes[i].material)];
        EXPECT_EQ(m.name, "floor") << i;
        EXPECT_FALSE(m.gltfPbr) << i;
    }
    try {
        loadWith("\"material\": \"gold\", ", "gold.json");
        ADD_FAILURE() << "an unknown material loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("objects[1].material: no material named \"gold\""), std::string::npos) << e.what();
    }
}

// "background" is a colour or "transparent" (misses get alpha 0); any other word names the key.
TEST(SceneLoader, BackgroundMayBeTransparent) {
    const LoadedScene clearLoaded = loadText(R"({"background": "transparent"})");
    const Scene& clear = clearLoaded.scene;
    EXPECT_TRUE(clear.transparentBackground);
    EXPECT_EQ(clear.background, Color(0.f));
    const LoadedScene redLoaded = loadText(R"({"background": [1, 0, 0]})");
    const Scene& red = redLoaded.scene;
    EXPECT_FALSE(red.transparentBackground);
    EXPECT_EQ(red.background, Color(1.f, 0.f, 0.f));
    EXPECT_NE(errorOf(R"({"background": "clear"})").find("background: expected [r, g, b] or \"transparent\""), std::string::npos);
}

TEST(SceneLoader, NumbersBeyondFloatRangeNameTheirJsonPath) {
    // Issue 14 #8: these loaded and the objects vanished from the picture.
    const std::string big = errorOf(R"({"objects": [{"type": "sphere", "center": [0,0,0], "radius": 1e20}]})");
    EXPECT_NE(big.find("x.json: objects[0].radius: number beyond the range"), std::string::npos) << big;
    const std::string eye = errorOf(R"({"camera": {"eye": [0, 1e39, 5]}})");
    EXPECT_NE(eye.find("x.json: camera.eye: number beyond the range"), std::string::npos) << eye;
}

TEST(SceneLoader, DuplicateKeyIsAnError) {
    // nlohmann keeps the last of two equal keys; the user meant one of them.
    const std::string e = errorOf(R"({"objects": [{"type": "sphere", "radius": 1, "radius": 2}]})");
    EXPECT_NE(e.find("x.json: objects[0].radius: duplicate key"), std::string::npos) << e;
}

TEST(SceneLoader, DeepNestingIsRefusedBeforeParsing) {
    const std::string e = errorOf("{\"comment\": " + std::string(20000, '[') + std::string(20000, ']') + "}");
    EXPECT_NE(e.find("x.json: JSON nests more than"), std::string::npos) << e;
}

TEST(SceneLoader, CameraUpParallelToTheViewGivesANote) {
    const LoadedScene sLoaded = loadText(R"({"camera": {"eye": [0, 5, 0], "target": [0, 0, 0], "up": [0, 1, 0]}})");
    const Scene& s = sLoaded.scene;
    int notes = 0;
    for (const std::string& n : s.notes) notes += n.find("camera.up is parallel to the view direction") != std::string::npos;
    EXPECT_EQ(notes, 1);
    const LoadedScene okLoaded = loadText(R"({"camera": {"eye": [0, 5, 5], "target": [0, 0, 0], "up": [0, 1, 0]}})");
    const Scene& ok = okLoaded.scene;
    EXPECT_TRUE(ok.notes.empty());
}
