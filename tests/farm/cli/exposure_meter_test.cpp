// The exposure meter poses a few frames of the film to meter them (farm/cli/exposure_meter.cpp)
// and must leave the scene as it was: a worker that never metered renders the same frames as
// rank 0. A timeline that moves only the camera and the lights (a static model's turntable) is
// posed in place with those two put back, not on a copy of the whole scene (anim::TrialPose);
// one that poses a model works on a copy. Checked on real files: the EV is the same either way,
// the camera and lights come back exactly, and a frame rendered after metering is the frame a
// scene never metered renders, byte for byte.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "anim/timeline.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "farm/cli/exposure_meter.h"

namespace rf::cli {
namespace {

const char* kBox = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";

LoadedScene load(const std::string& path) {
    DiskFileSource fs;
    SceneOptions o{};
    o.width = 48;
    o.height = 27;
    return loadScene(path, fs, o);
}

RenderSettings metered(LoadedScene& l, const anim::Timeline& tl, bool forceCopy) {
    RenderSettings s = l.scene.settings;
    s.width = 48, s.height = 27, s.spp = 1;
    s.autoExposure = true;
    if (forceCopy)
        resolveAutoExposure(l.scene, tl, s, 1, [](Scene&) {});  // a pose hook: always a copy
    else
        resolveAutoExposure(l.scene, tl, s, 1);
    return s;
}

bool sameCamera(const Camera& a, const Camera& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fovDeg == b.fovDeg && a.orthographic == b.orthographic &&
           a.orthoHalf == b.orthoHalf;
}

bool sameLights(const std::vector<Light>& a, const std::vector<Light>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!(a[i].position == b[i].position && a[i].direction == b[i].direction && a[i].color == b[i].color &&
              a[i].intensity == b[i].intensity))
            return false;
    return true;
}

Image frameAt(const Scene& scene, const anim::Timeline& tl, int f, const RenderSettings& s) {
    Scene posed = scene;
    tl.applyFrame(posed, f);
    RayStats rays;
    return renderFrame(posed, RenderView{posed.camera, s}, f, 1, rays);
}

}  // namespace

TEST(AutoExposure, AStaticTurntableIsMeteredInPlaceAndLeftAsItWas) {
    if (!std::filesystem::exists(kBox)) GTEST_SKIP() << kBox << " missing (assimp-testmodels)";
    LoadedScene l = load(kBox);
    const anim::Timeline tl = anim::Timeline::fromScene(l);
    ASSERT_FALSE(tl.isStill());
    ASSERT_FALSE(tl.posesModels());
    {
        anim::TrialPose trial(l.scene, tl);
        EXPECT_FALSE(trial.copied());
        EXPECT_EQ(&trial.scene(), &l.scene);
    }
    const Camera camera = l.scene.camera;
    const std::vector<Light> lights = l.scene.lights;
    const RenderSettings inPlace = metered(l, tl, false);
    EXPECT_TRUE(sameCamera(l.scene.camera, camera));
    EXPECT_TRUE(sameLights(l.scene.lights, lights));
    const RenderSettings copied = metered(l, tl, true);
    EXPECT_EQ(inPlace.exposure, copied.exposure);
    EXPECT_FALSE(inPlace.autoExposure);
    // The meter really posed other frames: the camera moved while it ran (a turntable's frame
    // 45 differs from frame 0), and came back.
    anim::TrialPose trial(l.scene, tl);
    tl.applyFrame(trial.scene(), tl.frameCount() / 4);
    EXPECT_FALSE(sameCamera(l.scene.camera, camera));

    // A frame after metering is the frame of a scene never metered.
    LoadedScene fresh = load(kBox);
    RenderSettings s = inPlace;
    const Image a = frameAt(l.scene, tl, 7, s), b = frameAt(fresh.scene, anim::Timeline::fromScene(fresh), 7, s);
    ASSERT_EQ(a.width(), b.width());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), sizeof(float) * 3 * size_t(a.width()) * size_t(a.height())), 0);
}

TEST(AutoExposure, AnAnimatedModelIsMeteredOnACopy) {
    LoadedScene l = load(std::string(RAYFARM_SOURCE_DIR) + "/scenes/animated_node.gltf");
    const anim::Timeline tl = anim::Timeline::fromScene(l);
    ASSERT_TRUE(tl.posesModels());
    const std::vector<Vec3> before = l.scene.geometry.meshes.at(0).positions;
    {
        anim::TrialPose trial(l.scene, tl);
        EXPECT_TRUE(trial.copied());
        EXPECT_NE(&trial.scene(), &l.scene);
    }
    const RenderSettings s = metered(l, tl, false);
    EXPECT_FALSE(s.autoExposure);
    EXPECT_EQ(l.scene.geometry.meshes.at(0).positions, before);
}

}  // namespace rf::cli
