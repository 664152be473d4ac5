#include "farm/view/camera_keys.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "engine/util/file_source.h"
#include "farm/view/orbit_camera.h"
#include "engine/load/scene_loader.h"

namespace rf::view {
namespace {

const char* kBox = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";

LoadedScene load(const std::string& path) {
    DiskFileSource fs;
    return loadScene(path, fs);
}

TEST(CameraKeys, KeysStaySortedAndOnePerTime) {
    CameraKeys k;
    EXPECT_EQ(k.add({1.0, DVec3(1.0), DVec3(0.0), 40.0}), 0);
    EXPECT_EQ(k.add({0.5, DVec3(2.0), DVec3(0.0), 40.0}), 0);
    EXPECT_EQ(k.add({2.0, DVec3(3.0), DVec3(0.0), 40.0}), 2);
    EXPECT_EQ(k.add({1.0, DVec3(4.0), DVec3(0.0), 30.0}), 1);  // replaces the key at 1 s
    ASSERT_EQ(k.keys().size(), 3u);
    EXPECT_EQ(k.keys()[1].eye, DVec3(4.0));
    EXPECT_EQ(k.keys()[1].fovDeg, 30.0);
    k.remove(0);
    EXPECT_EQ(k.keys().front().time, 1.0);
}

/// Saves keys for scenePath into dir, loads the saved file, and checks its timeline puts the
/// camera on each key bit for bit, with the film's frame count.
void checkSavedPath(const std::string& scenePath, const std::string& saved) {
    LoadedScene sceneLoaded = load(scenePath);
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    const Film film = filmOf(tl);
    Scene posed = scene;
    tl.applyFrame(posed, 0);
    const Camera a = orbit(posed.camera, 40.0, 10.0);
    const Camera b = zoom(pan(a, 5.0, -3.0, 90), 2.0);
    CameraKeys keys;
    keys.add(keyFromCamera(a, scene.renderOrigin, tl.frameTime(0)));
    keys.add(keyFromCamera(b, scene.renderOrigin, tl.frameTime(6)));
    RenderSettings s = scene.settings;
    s.width = 120;
    s.height = 90;
    s.spp = 4;
    writeSceneFile(saved, sceneDocument(scene, s, keyedTimeline(keys, sceneLoaded.timeline, film)));

    LoadedScene backLoaded = load(saved);
    Scene& back = backLoaded.scene;
    EXPECT_EQ(back.renderOrigin, scene.renderOrigin);
    EXPECT_EQ(back.settings.width, 120);
    EXPECT_EQ(back.settings.spp, 4);
    EXPECT_EQ(back.lights.size(), scene.lights.size());
    EXPECT_EQ(back.environment != nullptr, scene.environment != nullptr);
    EXPECT_EQ(back.settings.toneMap, scene.settings.toneMap);
    EXPECT_EQ(back.settings.autoExposure, scene.settings.autoExposure);
    const anim::Timeline btl = anim::Timeline::fromScene(backLoaded);
    EXPECT_EQ(btl.frameCount(), film.frames);
    EXPECT_DOUBLE_EQ(btl.fps(), film.fps);
    for (auto [frame, cam] : {std::pair{0, a}, std::pair{6, b}}) {
        btl.applyFrame(back, frame);
        EXPECT_EQ(back.camera.eye, cam.eye) << frame;
        EXPECT_EQ(back.camera.target, cam.target) << frame;
        EXPECT_EQ(back.camera.fovDeg, cam.fovDeg) << frame;
    }
}

TEST(CameraKeys, SavedJsonSceneReplaysTheKeysExactly) {
    const std::string dir = ::testing::TempDir();
    checkSavedPath(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", dir + "/keys_whitted.json");
}

TEST(CameraKeys, SavedBareModelBecomesASceneThatReplaysTheKeys) {
    if (!std::filesystem::exists(kBox)) GTEST_SKIP() << kBox << " missing (assimp-testmodels)";
    const std::string saved = ::testing::TempDir() + "/keys_box.json";
    checkSavedPath(kBox, saved);
    std::ifstream f(saved);
    const nlohmann::json doc = nlohmann::json::parse(f);
    EXPECT_EQ(doc["objects"][0]["path"], kBox);
    EXPECT_EQ(doc["lights"].size(), 1u);  // the default key light, written out
    ASSERT_TRUE(doc.contains("environment"));  // and the built-in studio that lights the rest
    EXPECT_FALSE(doc["environment"].contains("file"));
}

TEST(CameraKeys, ModelPathsOfAJsonSceneBecomeAbsolute) {
    LoadedScene sceneLoaded = load(std::string(RAYFARM_SOURCE_DIR) + "/scenes/model_on_floor.json");
    Scene& scene = sceneLoaded.scene;
    CameraKeys keys;
    keys.add(keyFromCamera(scene.camera, scene.renderOrigin, 0.0));
    const nlohmann::json doc = sceneDocument(scene, scene.settings, keyedTimeline(keys, sceneLoaded.timeline, filmOf(anim::Timeline::fromScene(sceneLoaded))));
    for (const auto& o : doc["objects"]) {
        if (o["type"] == "model") {
            EXPECT_TRUE(std::filesystem::path(o["path"].get<std::string>()).is_absolute());
        }
    }
    EXPECT_FALSE(doc.contains("turntable"));
    EXPECT_EQ(doc["timeline"]["camera"]["position"]["keys"].size(), 1u);
}

}  // namespace
}  // namespace rf::view
