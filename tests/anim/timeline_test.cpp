// The timeline format end to end: JSON scenes through the real loader, errors naming file and key,
// the POV-Ray orbit of scenes/whitted.json, light tracks and film lengths.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::anim {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string outDir() {
    std::string d = RAYFARM_TEST_OUT;  // appended, not operator+: GCC 12 warns falsely under LTO
    d += "/anim";
    std::filesystem::create_directories(d);
    return d;
}

/// Writes a small scene (two lights, a sphere) with the given extra top-level JSON and loads it.
std::string writeScene(const std::string& name, const std::string& extra) {
    const std::string path = outDir() + "/" + name;
    std::ofstream(path) << R"({
  "camera": { "eye": [0, 2, 10], "target": [0, 1, 0] },
  "lights": [ { "type": "point", "name": "key", "position": [5, 5, 5] },
              { "type": "spot", "name": "spot", "position": [0, 4, 0], "direction": [0, -1, 0], "outer_angle": 30 } ],
  "objects": [ { "type": "sphere", "center": [0, 1, 0], "radius": 1 } ])"
                        << (extra.empty() ? "" : ",\n" + extra) << "\n}\n";
    return path;
}

LoadedScene load(const std::string& path) {
    DiskFileSource fs;
    return loadScene(path, fs);
}

/// The InputError message for a timeline, or "" if it loaded.
std::string timelineError(const std::string& name, const std::string& extra) {
    const std::string path = writeScene(name, extra);
    try {
        Timeline::fromScene(load(path));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Timeline, JsonSceneWithoutTimelineIsOneStillFrame) {
    LoadedScene sLoaded = load(writeScene("still.json", ""));
    Scene& s = sLoaded.scene;
    const Camera before = s.camera;
    const Timeline tl = Timeline::fromScene(sLoaded);
    EXPECT_EQ(tl.frameCount(), 1);
    EXPECT_TRUE(tl.isStill());
    tl.applyFrame(s, 0);
    EXPECT_EQ(s.camera.eye, before.eye);
}

// Case 27 in the file format: the error names the file and the key.
TEST(Timeline, EqualAndUnsortedKeyTimesNameFileAndKey) {
    const std::string keys = R"("timeline": { "camera": { "position": { "keys": [
        {"time": 0, "value": [0, 2, 10]}, {"time": 1, "value": [1, 2, 10]},
        {"time": 2, "value": [2, 2, 10]}, {"time": TIME, "value": [3, 2, 10]} ] } } })";
    for (const char* bad : {"2", "1.5"}) {
        std::string extra = keys;
        extra.replace(extra.find("TIME"), 4, bad);
        const std::string path = outDir() + "/unsorted.json";
        const std::string msg = timelineError("unsorted.json", extra);
        EXPECT_EQ(msg.rfind(path + ": timeline.camera.position.keys[3].time: times must increase", 0), 0u) << msg;
    }
}

TEST(Timeline, BadTracksAreRejectedClearly) {
    struct Case {
        const char* extra;
        const char* expect;
    } cases[] = {
        {R"("timeline": {"lights": [{"light": "nope", "intensity": [{"time": 0, "value": 1}]}]})",
         "timeline.lights[0].light: no light named \"nope\""},
        {R"("timeline": {"lights": [{"light": 7}]})", "timeline.lights[0].light: no light 7 (the scene has 2)"},
        {R"("timeline": {"camera": {"fov": [{"time": 0, "value": 200}]}})", "timeline.camera.fov[0].value: expected degrees in (0, 180)"},
        {R"("timeline": {"camera": {"position": {"interpolation": "bouncy", "keys": [{"time": 0, "value": [0,0,0]}]}}})",
         "timeline.camera.position.interpolation: unknown interpolation \"bouncy\""},
        {R"("timeline": {"camera": {"position": [{"time": 0, "value": [0,0,0], "interpolation": "slerp"}]}})",
         "timeline.camera.position[0].interpolation: slerp is for orientation tracks"},
        {R"("timeline": {"camera": {"orientation": [{"time": 0, "value": [0,0,0,0]}]}})",
         "timeline.camera.orientation[0].value: a rotation quaternion must not be zero"},
        {R"("timeline": {"camera": {"position": [{"time": 0}]}})", "timeline.camera.position[0]: a key needs a \"value\""},
        {R"("timeline": {"camera": {"position": [{"time": 0, "value": [1, 2]}]}})", "timeline.camera.position[0].value: expected 3 numbers"},
        {R"("timeline": {"speed": 2})", "timeline.speed: unknown key"},
        {R"("timeline": {"animation": {"model": 0}})", "timeline.animation.model: no model 0 (the scene has 0)"},
        {R"("timeline": {}, "turntable": {})", "turntable: give either a timeline or a turntable"},
        {R"("turntable": {"lights": "sideways"})", "turntable.lights: expected \"fixed\" or \"follow-camera\""},
        // A rate MP4 cannot carry: the first frame's write would fail after the render.
        {R"("timeline": {"fps": 1e-9})", "timeline.fps: expected a rate from 0.001 (a frame every 1000 s) up to 1000"},
        {R"("turntable": {"fps": 5000})", "turntable.fps: expected a rate from 0.001 (a frame every 1000 s) up to 1000"},
    };
    for (const Case& c : cases) {
        const std::string msg = timelineError("bad.json", c.extra);
        EXPECT_EQ(msg.rfind(outDir() + "/bad.json: " + c.expect, 0), 0u) << "got: " << msg << "\nfor: " << c.extra;
    }
}

TEST(Timeline, FilmsIncludeBothEndsLoopsDoNot) {
    const char* film = R"("timeline": {"fps": 30, "duration": 4})";
    EXPECT_EQ(Timeline::fromScene(load(writeScene("film.json", film))).frameCount(), 121);
    const char* loop = R"("timeline": {"fps": 30, "duration": 4, "loop": true})";
    EXPECT_EQ(Timeline::fromScene(load(writeScene("loop.json", loop))).frameCount(), 120);
    const char* frames = R"("timeline": {"fps": 24, "frames": 10, "start": 2})";
    const Timeline tl = Timeline::fromScene(load(writeScene("frames.json", frames)));
    EXPECT_EQ(tl.frameCount(), 10);
    EXPECT_DOUBLE_EQ(tl.frameTime(3), 2.0 + 3.0 / 24.0);
    // Without a duration, the last key sets the length.
    const char* keyed = R"("timeline": {"fps": 10, "camera": {"fov": [{"time": 0, "value": 40}, {"time": 2.5, "value": 50}]}})";
    EXPECT_EQ(Timeline::fromScene(load(writeScene("keyed.json", keyed))).frameCount(), 26);
}

// scenes/whitted.json carries whitted.pov's orbit: eye (8 sin 2πc, 3, −8 cos 2πc), c = i/30 over
// 31 frames (POV's +KFI0 +KFF30 +KI0 +KF1), so frame 30 repeats frame 0.
TEST(Timeline, WhittedOrbitMatchesPovRayClock) {
    const std::string path = std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json";
    const LoadedScene loadedLoaded = load(path);
    const Scene& loaded = loadedLoaded.scene;
    const Timeline tl = Timeline::fromScene(loadedLoaded);
    ASSERT_EQ(tl.frameCount(), 31);
    Scene s = loaded;
    tl.applyFrame(s, 0);
    // The still default (frame 0) is the scene's own camera, bit for bit.
    EXPECT_EQ(std::memcmp(&s.camera.eye, &loaded.camera.eye, sizeof(Vec3)), 0);
    EXPECT_EQ(s.camera.target, loaded.camera.target);
    EXPECT_EQ(s.camera.up, loaded.camera.up);
    EXPECT_EQ(s.camera.fovDeg, loaded.camera.fovDeg);
    for (int i = 0; i <= 30; ++i) {
        tl.applyFrame(s, i);
        const double c = i / 30.0;
        const DVec3 want = DVec3(8 * std::sin(2 * kPi * c), 3, -8 * std::cos(2 * kPi * c)) - loaded.renderOrigin;
        EXPECT_NEAR(glm::length(DVec3(s.camera.eye) - want), 0.0, 1e-5) << "frame " << i;
        EXPECT_EQ(s.camera.target, loaded.camera.target);
    }
    Scene a = loaded, b = loaded;
    tl.applyFrame(a, 0);
    tl.applyFrame(b, 30);
    EXPECT_NEAR(glm::length(a.camera.eye - b.camera.eye), 0.f, 1e-5f);
}

TEST(Timeline, LightTracksByNameAndIndexAreAbsolute) {
    const char* extra = R"("timeline": {"lights": [
        {"light": "spot", "position": [{"time": 0, "value": [0, 4, 0]}, {"time": 2, "value": [4, 4, 0]}],
         "color": [{"time": 0, "value": [1, 0, 0]}, {"time": 2, "value": 0.5}],
         "outer_angle": [{"time": 0, "value": 30}, {"time": 2, "value": 50}],
         "direction": [{"time": 0, "value": [0, -2, 0]}, {"time": 2, "value": [2, 0, 0]}]},
        {"light": 0, "intensity": [{"time": 0, "value": 1}, {"time": 1, "value": 3, "interpolation": "step"}, {"time": 2, "value": 0}]}]})";
    const LoadedScene loadedLoaded = load(writeScene("lights.json", extra));
    const Scene& loaded = loadedLoaded.scene;
    const Timeline tl = Timeline::fromScene(loadedLoaded);
    Scene s = loaded;
    tl.apply(s, 1.0);
    EXPECT_NEAR(glm::length(s.lights[1].position - Vec3(2, 4, 0)), 0.f, 1e-6f);
    EXPECT_NEAR(glm::length(s.lights[1].color - Color(0.75f, 0.25f, 0.25f)), 0.f, 1e-6f);
    EXPECT_NEAR(s.lights[1].outerCone, glm::radians(40.0), 1e-6);
    EXPECT_NEAR(glm::length(s.lights[1].direction - glm::normalize(Vec3(1, -1, 0))), 0.f, 1e-6f);
    EXPECT_EQ(s.lights[0].intensity, 3.f);  // exactly at the key
    tl.apply(s, 1.5);
    EXPECT_EQ(s.lights[0].intensity, 3.f);  // step holds
    tl.apply(s, 0.0);  // going back in time restores frame 0 exactly
    EXPECT_EQ(s.lights[1].position, loaded.lights[1].position);
    EXPECT_EQ(s.lights[0].intensity, 1.f);
    EXPECT_EQ(s.lights[0].position, loaded.lights[0].position);  // untracked: untouched
}

TEST(Timeline, OrientationTrackSetsTargetAndUp) {
    // A quarter turn about y: the camera's −z view becomes −x.
    const double h = std::sqrt(0.5);
    const std::string extra = R"("timeline": {"camera": {"position": [{"time": 0, "value": [0, 2, 10]}],
        "orientation": [{"time": 0, "value": [0, 0, 0, 1]}, {"time": 1, "value": [0, )" +
                              std::to_string(h) + ", 0, " + std::to_string(h) + "]}]}}";
    LoadedScene sLoaded = load(writeScene("orient.json", extra));
    Scene& s = sLoaded.scene;
    const Timeline tl = Timeline::fromScene(sLoaded);
    tl.apply(s, 1.0);
    const Vec3 fwd = s.camera.target - s.camera.eye;
    EXPECT_NEAR(glm::length(fwd - Vec3(-1, 0, 0)), 0.f, 1e-5f);
    EXPECT_NEAR(glm::length(s.camera.up - Vec3(0, 1, 0)), 0.f, 1e-5f);
    tl.apply(s, 0.5);
    EXPECT_NEAR(glm::length(glm::normalize(s.camera.target - s.camera.eye) - glm::normalize(Vec3(-1, 0, -1))), 0.f, 1e-5f);
}

// Positions in the file are world space; the scene works in render space = world − renderOrigin.
TEST(Timeline, WorldPositionsAreRebasedToTheRenderOrigin) {
    const std::string path = outDir() + "/far.json";
    std::ofstream(path) << R"({"camera": {"eye": [100000, 2, 10], "target": [100000, 1, 0]},
      "objects": [{"type": "sphere", "center": [100000, 1, 0], "radius": 1}],
      "timeline": {"camera": {"position": [{"time": 0, "value": [100000, 2, 10]}, {"time": 1, "value": [100004, 2, 10]}]}}})";
    LoadedScene sLoaded = load(path);
    Scene& s = sLoaded.scene;
    ASSERT_NE(s.renderOrigin.x, 0.0);
    const Timeline tl = Timeline::fromScene(sLoaded);
    tl.apply(s, 0.25);
    EXPECT_NEAR(double(s.camera.eye.x) + s.renderOrigin.x, 100001.0, 1e-6);
}

// A timeline in its own file is read through the FileSource (so it travels in the farm's
// bundle) and its errors name that file.
TEST(Timeline, SeparateTimelineFileTravelsInTheBundleAndNamesItself) {
    const std::string tlPath = outDir() + "/orbit_timeline.json";
    std::ofstream(tlPath) << R"({"fps": 10, "duration": 2, "camera": {"orbit": {"radius": 5, "height": 2, "period": 2}}})";
    const std::string scenePath = writeScene("with_file.json", R"("timeline": "orbit_timeline.json")");
    DiskFileSource disk;
    EXPECT_EQ(Timeline::fromScene(loadScene(scenePath, disk)).frameCount(), 21);
    // A worker that only has the bundle loads the same film.
    BundleFileSource bundle(disk.bundle());
    LoadedScene wLoaded = loadScene(scenePath, bundle);
    Scene& w = wLoaded.scene;
    const Timeline tl = Timeline::fromScene(wLoaded);
    tl.applyFrame(w, 5);  // c = 0.25: eye at (5, 2, 0)
    EXPECT_NEAR(glm::length(DVec3(w.camera.eye) + w.renderOrigin - DVec3(5, 2, 0)), 0.0, 1e-5);

    std::ofstream(tlPath) << R"({"camera": {"fov": [{"time": 1, "value": 40}, {"time": 1, "value": 50}]}})";
    DiskFileSource disk2;
    try {
        Timeline::fromScene(loadScene(scenePath, disk2));
        FAIL() << "equal times accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(tlPath + ": camera.fov[1].time: times must increase", 0), 0u) << e.what();
    }
}

TEST(Timeline, TurntableSectionOrbitsTheBounds) {
    const char* extra = R"("turntable": {"seconds": 2, "fps": 10, "elevation": 0, "distance": 6, "lights": "follow-camera"})";
    LoadedScene sLoaded = load(writeScene("turn.json", extra));
    Scene& s = sLoaded.scene;
    const Timeline tl = Timeline::fromScene(sLoaded);
    ASSERT_EQ(tl.frameCount(), 20);
    tl.applyFrame(s, 5);  // a quarter turn: camera on +x of the sphere centre (0, 1, 0)
    EXPECT_NEAR(glm::length(DVec3(s.camera.eye) + s.renderOrigin - DVec3(6, 1, 0)), 0.0, 1e-5);
}

}  // namespace
}  // namespace rf::anim
