// Issue 42: a file's camera drives the film (--camera N), following its node's animation and its
// parents', as a pure function of the frame; every animation of a file plays together
// (--animation all, and the default when they move different nodes); --scene N picks a scene.
//
// The analytic file: a cube of half size 0.25 at the origin; a "rig" node whose translation is
// keyed (0, 0, 5) → (0, 1, 5) over 1 s ("RigLift"), and under it a perspective camera (yfov 60°)
// keyed (0, 0, 0) → (2, 0, 0) over 2 s ("CamSlide") and a still orthographic one (ymag 1). Both
// look down −z at the cube, so where the cube appears at a time follows from the keys alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "anim/gltf_animation.h"
#include "anim/timeline.h"
#include "anim/timeline_spec.h"
#include "engine/geometry/camera.h"
#include "engine/load/scene_loader.h"
#include "engine/util/errors.h"
#include "engine/util/file_source.h"

using namespace rf;

namespace {

const std::string kOut = std::string(RAYFARM_TEST_OUT) + "/file-camera";
const std::string kBlender = std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/animated_camera.gltf";

std::string base64(const std::vector<uint8_t>& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        const uint32_t n = (uint32_t(in[i]) << 16) | (i + 1 < in.size() ? uint32_t(in[i + 1]) << 8 : 0) | (i + 2 < in.size() ? in[i + 2] : 0);
        out += t[(n >> 18) & 63];
        out += t[(n >> 12) & 63];
        out += i + 1 < in.size() ? t[(n >> 6) & 63] : '=';
        out += i + 2 < in.size() ? t[n & 63] : '=';
    }
    return out;
}

template <class T>
void put(std::vector<uint8_t>& b, std::initializer_list<T> v) {
    for (T x : v) {
        uint8_t bytes[sizeof(T)];
        std::memcpy(bytes, &x, sizeof(T));
        b.insert(b.end(), bytes, bytes + sizeof(T));
    }
}

/// Writes the analytic file described above and returns its path.
std::string writeRigFile() {
    std::vector<uint8_t> b;
    const float h = 0.25f;
    put<float>(b, {-h, -h, -h, h, -h, -h, h, h, -h, -h, h, -h, -h, -h, h, h, -h, h, h, h, h, -h, h, h});  // 0..95
    put<uint16_t>(b, {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5});  // 96..167
    put<float>(b, {0.f, 2.f});                                 // 168: CamSlide times
    put<float>(b, {0.f, 0.f, 0.f, 2.f, 0.f, 0.f});             // 176: camera translation
    put<float>(b, {0.f, 1.f});                                 // 200: RigLift times
    put<float>(b, {0.f, 0.f, 5.f, 0.f, 1.f, 5.f});             // 208: rig translation
    const std::string json = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 1]}, {"nodes": [0]}],
  "nodes": [
    {"name": "cube", "mesh": 0},
    {"name": "rig", "translation": [0, 0, 5], "children": [2, 3]},
    {"name": "eye", "camera": 0},
    {"name": "flat", "camera": 1}
  ],
  "cameras": [
    {"type": "perspective", "perspective": {"yfov": 1.0471975511965976, "znear": 0.01}},
    {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.01, "zfar": 100}}
  ],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
  "animations": [
    {"name": "CamSlide", "samplers": [{"input": 2, "output": 3}], "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"}}]},
    {"name": "RigLift", "samplers": [{"input": 4, "output": 5}], "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}]}
  ],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [-0.25, -0.25, -0.25], "max": [0.25, 0.25, 0.25]},
    {"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"},
    {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [2]},
    {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"},
    {"bufferView": 4, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [1]},
    {"bufferView": 5, "componentType": 5126, "count": 2, "type": "VEC3"}
  ],
  "bufferViews": [
    {"buffer": 0, "byteOffset": 0, "byteLength": 96},
    {"buffer": 0, "byteOffset": 96, "byteLength": 72},
    {"buffer": 0, "byteOffset": 168, "byteLength": 8},
    {"buffer": 0, "byteOffset": 176, "byteLength": 24},
    {"buffer": 0, "byteOffset": 200, "byteLength": 8},
    {"buffer": 0, "byteOffset": 208, "byteLength": 24}
  ],
  "buffers": [{"byteLength": 232, "uri": "data:application/octet-stream;base64,)" +
                             base64(b) + R"("}]
})";
    std::filesystem::create_directories(kOut);
    const std::string path = kOut + "/rig.gltf";
    std::ofstream(path) << json;
    return path;
}

/// Loads at 65×65 with --camera, --animation and --scene as given (-1 / "": not given).
LoadedScene load(const std::string& path, int camera = -1, const std::string& animation = "", int scene = -1) {
    SceneOptions o{};
    o.width = 65;
    o.height = 65;
    if (camera >= 0) o.camera = camera;
    if (!animation.empty()) o.animation = animation;
    o.assets.scene = scene;
    DiskFileSource fs;
    return loadScene(path, fs, o);
}

/// Centre of the pixels whose centre ray hits something, as the scene's camera sees it.
struct Seen {
    int pixels = 0;
    double x = 0.0, y = 0.0;
};
Seen seen(const Scene& scene, int w, int h) {
    const CameraRays rays(scene.camera, w, h);
    Seen s;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            Hit hit;
            if (!scene.geometry.intersect(rays.generate(x + 0.5f, y + 0.5f), hit)) continue;
            ++s.pixels;
            s.x += x + 0.5;
            s.y += y + 0.5;
        }
    if (s.pixels) s.x /= s.pixels, s.y /= s.pixels;
    return s;
}

/// Where the origin lands in pixels for a camera at (cx, cy, 5) looking down −z: perspective
/// with tan(half fov) = tanHalf, or orthographic with half height tanHalf·5.
void expected(double cx, double cy, double tanHalf, int w, int h, double& px, double& py) {
    px = 0.5 * w * (1.0 + (-cx / 5.0) / tanHalf);
    py = 0.5 * h * (1.0 - (-cy / 5.0) / tanHalf);
}

TEST(FileCamera, FollowsItsNodeAndItsParentFrameByFrame) {
    const LoadedScene loaded = load(writeRigFile(), 0);
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    // Both animations play (they move different nodes); the camera moves with both, the longer
    // (CamSlide, 2 s) sets the film: both ends at 30 fps.
    EXPECT_EQ(tl.frameCount(), 61);
    EXPECT_DOUBLE_EQ(tl.fileCameraPeriod(), 2.0);
    ASSERT_EQ(tl.clips().size(), 2u);
    const double tan30 = std::tan(3.14159265358979 / 6.0);
    struct Case {
        int frame;
        double cx, cy;
    };
    // Frame 15 (0.5 s): slide 0.5, lift 0.5. Frame 45 (1.5 s): slide 1.5, lift looped to 0.5.
    // Frame 60 (2 s, the last): the slide holds its last key (2), the 1 s lift has looped to 0.
    for (const Case c : {Case{0, 0.0, 0.0}, Case{15, 0.5, 0.5}, Case{45, 1.5, 0.5}, Case{60, 2.0, 0.0}}) {
        Scene s = loaded.scene;
        tl.applyFrame(s, c.frame);
        EXPECT_NEAR(s.camera.eye.x, c.cx, 1e-5) << "frame " << c.frame;
        EXPECT_NEAR(s.camera.eye.y, c.cy, 1e-5) << "frame " << c.frame;
        const Seen v = seen(s, 65, 65);
        double px, py;
        expected(c.cx, c.cy, tan30, 65, 65, px, py);
        ASSERT_GT(v.pixels, 20) << "frame " << c.frame;
        EXPECT_NEAR(v.x, px, 1.0) << "frame " << c.frame;
        EXPECT_NEAR(v.y, py, 1.0) << "frame " << c.frame;
    }
    // A pure function of the frame: the same frame after others gives the same camera.
    Scene a = loaded.scene, b = loaded.scene;
    tl.applyFrame(a, 45);
    tl.applyFrame(b, 7);
    tl.applyFrame(b, 60);
    tl.applyFrame(b, 45);
    EXPECT_EQ(a.camera.eye, b.camera.eye);
    EXPECT_EQ(a.camera.target, b.camera.target);
}

TEST(FileCamera, OrthographicFollowsTheParent) {
    const LoadedScene loaded = load(writeRigFile(), 1);
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    // Only RigLift (1 s) moves this camera: the film is one play of it, both ends.
    EXPECT_EQ(tl.frameCount(), 31);
    Scene s = loaded.scene;
    tl.applyFrame(s, 15);
    ASSERT_TRUE(s.camera.orthographic);
    EXPECT_NEAR(s.camera.eye.y, 0.5, 1e-5);
    const Seen v = seen(s, 65, 65);
    double px, py;
    expected(0.0, 0.5, 1.0 / 5.0, 65, 65, px, py);  // half height 1 at any distance
    EXPECT_NEAR(v.x, px, 1.0);
    EXPECT_NEAR(v.y, py, 1.0);
}

TEST(FileCamera, ChosenAnimationOnlyMovesWhatItAnimates) {
    const LoadedScene loaded = load(writeRigFile(), 0, "RigLift");
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    EXPECT_EQ(tl.frameCount(), 31);
    Scene s = loaded.scene;
    tl.applyFrame(s, 15);
    EXPECT_NEAR(s.camera.eye.x, 0.0, 1e-6);  // CamSlide does not play
    EXPECT_NEAR(s.camera.eye.y, 0.5, 1e-5);
}

TEST(FileCamera, ACameraTheFileLacksIsRefusedNamingIt) {
    const LoadedScene loaded = load(writeRigFile(), 2);
    try {
        (void)anim::Timeline::fromScene(loaded);
        FAIL() << "camera 2 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--camera: no camera 2 (the file has 2 cameras)"), std::string::npos) << e.what();
    }
}

TEST(FileCamera, BareModelWithoutCameraStaysATurntable) {
    const LoadedScene loaded = load(writeRigFile());
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    EXPECT_FALSE(tl.fileCamera());
    EXPECT_EQ(tl.frameCount(), 120);  // 4 s: two whole plays of the 2 s clip
    ASSERT_EQ(tl.clips().size(), 2u);
}

TEST(AllAnimations, DefaultPlaysThoseOnDifferentNodesAllPlaysEvery) {
    SceneGraph g;
    g.nodes.resize(3);
    auto anim = [](const char* name, int node, AnimPath path) {
        Animation a;
        a.name = name;
        AnimSampler s;
        s.times = {0.f, 1.f};
        s.values = path == AnimPath::Rotation ? std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1} : std::vector<float>{0, 0, 0, 1, 1, 1};
        s.components = path == AnimPath::Rotation ? 4 : 3;
        a.samplers.push_back(s);
        a.channels.push_back({0, node, path});
        return a;
    };
    g.animations = {anim("a", 0, AnimPath::Translation), anim("b", 1, AnimPath::Translation), anim("c", 0, AnimPath::Translation),
                    anim("d", 0, AnimPath::Rotation)};
    EXPECT_EQ(anim::defaultAnimations(g), (std::vector<int>{0, 1, 3}));  // c retakes a's property
    Scene scene;
    scene.geometry.models.push_back(g);
    const std::vector<anim::GltfAnimationPlayer> all = anim::chosenPlayers(scene, "all", "f.gltf", "--animation");
    ASSERT_EQ(all.size(), 1u);
    EXPECT_EQ(all[0].animations(), (std::vector<int>{0, 1, 2, 3}));
    const std::vector<anim::GltfAnimationPlayer> def = anim::defaultPlayers(scene);
    ASSERT_EQ(def.size(), 1u);
    EXPECT_EQ(def[0].animations(), (std::vector<int>{0, 1, 3}));
}

// Blender 3.4's own export (tests/reference/make_animated_camera.py): one animation per object,
// a camera flown over 2 s, two scenes of which the second ("Stage") is the file's default.
TEST(BlenderExport, EveryObjectsAnimationPlaysAndTheCameraSetsTheFilm) {
    const LoadedScene loaded = load(kBlender, 0);
    ASSERT_EQ(loaded.scene.gltfCameras.size(), 1u);  // Stage's FlyCam only
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    EXPECT_EQ(tl.clips().size(), 4u);  // RedSpin, GreenHop, BlueSlide, CameraFly together
    EXPECT_NEAR(tl.fileCameraPeriod(), 2.0 + 1.0 / 24.0, 1e-4);
    EXPECT_EQ(tl.frameCount(), 62);  // round(49/24 s × 30 fps) + 1
    // Blender's keys (Z up) as glTF's Y up: (x, y, z) → (x, z, −y). The first key is at 1/24 s
    // (Blender's frame 1); before it the first key holds: (7, −7, 3) → (7, 3, 7).
    Scene s = loaded.scene;
    tl.applyFrame(s, 0);
    EXPECT_NEAR(s.camera.eye.x, 7.0, 1e-3);
    EXPECT_NEAR(s.camera.eye.y, 3.0, 1e-3);
    EXPECT_NEAR(s.camera.eye.z, 7.0, 1e-3);
    // Frame 60 is 2 s, Blender's frame 48: 15/16 of the way from the key at frame 33
    // (−4, −8, 3.5) to the one at 49 (−8, −4, 2.5), linear.
    tl.applyFrame(s, 60);
    EXPECT_NEAR(s.camera.eye.x, -7.75, 1e-3);
    EXPECT_NEAR(s.camera.eye.y, 2.5625, 1e-3);
    EXPECT_NEAR(s.camera.eye.z, 4.25, 1e-3);
    // At Blender's own 24 fps the last frame falls on the last key, and holds it instead of
    // looping back to the first: (−8, −4, 2.5) → (−8, 2.5, 4).
    const anim::Timeline at24 = anim::Timeline::fromScene(loaded, 24.0);
    EXPECT_EQ(at24.frameCount(), 50);
    at24.applyFrame(s, 49);
    EXPECT_NEAR(s.camera.eye.x, -8.0, 1e-3);
    EXPECT_NEAR(s.camera.eye.y, 2.5, 1e-3);
    EXPECT_NEAR(s.camera.eye.z, 4.0, 1e-3);
}

TEST(BlenderExport, SceneOptionPicksTheOtherScene) {
    const LoadedScene stage = load(kBlender);
    const LoadedScene spare = load(kBlender, -1, "", 0);
    EXPECT_EQ(stage.scene.geometry.meshes.size(), 4u);  // floor and three cubes
    EXPECT_EQ(spare.scene.geometry.meshes.size(), 1u);  // the ball
    ASSERT_EQ(spare.scene.gltfCameras.size(), 1u);
    try {
        (void)load(kBlender, -1, "", 2);
        FAIL() << "scene 2 accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--scene: no scene 2 (the file has 2 scenes)"), std::string::npos) << e.what();
    }
}

}  // namespace
