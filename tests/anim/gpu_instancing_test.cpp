// EXT_mesh_gpu_instancing (issue 42, item 3): a node draws its mesh once per instance, placed by
// the instance's TRANSLATION, ROTATION and SCALE inside the node's space. Checked analytically:
// unit cubes at known places, seen straight down the z axis through an orthographic camera 10 x
// 10 units wide at 10 pixels a unit, cover exactly the pixels their squares cover (pixel centres);
// the node's own transform and its animation move every instance; `info` counts them; malformed
// instancing is refused naming the node and attribute. The files are written by the test itself
// (Blender 3.4's glTF exporter does not write the extension).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "anim/timeline.h"
#include "engine/geometry/camera.h"
#include "engine/load/gltf/gltf_inspect.h"
#include "engine/load/scene_loader.h"
#include "engine/util/errors.h"
#include "engine/util/image.h"

namespace rf::anim {
namespace {

using json = nlohmann::json;

std::string base64(const std::vector<unsigned char>& b) {
    static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < b.size(); i += 3) {
        const uint32_t v = uint32_t(b[i]) << 16 | uint32_t(i + 1 < b.size() ? b[i + 1] : 0) << 8 | uint32_t(i + 2 < b.size() ? b[i + 2] : 0);
        out += k[v >> 18 & 63];
        out += k[v >> 12 & 63];
        out += i + 1 < b.size() ? k[v >> 6 & 63] : '=';
        out += i + 2 < b.size() ? k[v & 63] : '=';
    }
    return out;
}

struct Instance {
    float t[3];
    float r[4];  // quaternion x, y, z, w
    float s[3];
};

/// A unit cube (corners at ±0.5) on node 0, drawn once per instance; an orthographic camera on
/// node 1 at z = 10 looking down −z, 10 units across; node 0 moves by +2 in x over one second
/// when animated.
json cubes(const std::vector<Instance>& inst, bool animated = false) {
    std::vector<unsigned char> buf;
    json views = json::array(), accessors = json::array();
    auto add = [&](const void* data, size_t bytes, int count, const char* type, int component, json minMax = nullptr) {
        while (buf.size() % 4) buf.push_back(0);
        views.push_back({{"buffer", 0}, {"byteOffset", buf.size()}, {"byteLength", bytes}});
        const auto* p = static_cast<const unsigned char*>(data);
        buf.insert(buf.end(), p, p + bytes);
        json a = {{"bufferView", int(views.size()) - 1}, {"componentType", component}, {"count", count}, {"type", type}};
        if (!minMax.is_null()) a["min"] = minMax[0], a["max"] = minMax[1];
        accessors.push_back(a);
        return int(accessors.size()) - 1;
    };
    std::vector<float> pos;
    for (int c = 0; c < 8; ++c)
        for (int k = 0; k < 3; ++k) pos.push_back((c >> k & 1) ? 0.5f : -0.5f);
    const std::vector<uint16_t> idx = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                       2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    const int posAcc = add(pos.data(), pos.size() * 4, 8, "VEC3", 5126, json{{-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}});
    const int idxAcc = add(idx.data(), idx.size() * 2, int(idx.size()), "SCALAR", 5123);
    std::vector<float> t, r, s;
    for (const Instance& i : inst) {
        t.insert(t.end(), i.t, i.t + 3);
        r.insert(r.end(), i.r, i.r + 4);
        s.insert(s.end(), i.s, i.s + 3);
    }
    json node0 = {{"mesh", 0}, {"name", "cubes"}};
    if (!inst.empty()) {
        const int n = int(inst.size());
        node0["extensions"] = {{"EXT_mesh_gpu_instancing",
                                {{"attributes",
                                  {{"TRANSLATION", add(t.data(), t.size() * 4, n, "VEC3", 5126)},
                                   {"ROTATION", add(r.data(), r.size() * 4, n, "VEC4", 5126)},
                                   {"SCALE", add(s.data(), s.size() * 4, n, "VEC3", 5126)}}}}}};
    }
    json g = {{"asset", {{"version", "2.0"}}},
              {"scene", 0},
              {"scenes", {{{"nodes", {0, 1}}}}},
              {"nodes", {node0, {{"camera", 0}, {"translation", {0, 0, 10}}}}},
              {"cameras", {{{"type", "orthographic"}, {"orthographic", {{"xmag", 5}, {"ymag", 5}, {"znear", 0.1}, {"zfar", 100}}}}}},
              {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", posAcc}}}, {"indices", idxAcc}}}}}}}};
    if (!inst.empty()) g["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    if (animated) {
        const float times[2] = {0.f, 1.f}, moves[6] = {0, 0, 0, 2, 0, 0};
        const int in = add(times, sizeof times, 2, "SCALAR", 5126, json{{0.0}, {1.0}});
        const int out = add(moves, sizeof moves, 2, "VEC3", 5126);
        json sampler = {{"input", in}, {"output", out}, {"interpolation", "LINEAR"}};
        json channel = {{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}};
        json animation = json::object();
        animation["samplers"] = json::array({sampler});
        animation["channels"] = json::array({channel});
        g["animations"] = json::array({animation});
    }
    g["bufferViews"] = views;
    g["accessors"] = accessors;
    g["buffers"] = {{{"byteLength", buf.size()}, {"uri", "data:application/octet-stream;base64," + base64(buf)}}};
    return g;
}

std::string writeFile(const json& g, const std::string& name) {
    // Named after the test too: ctest runs this file's tests in parallel processes.
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    const std::string dir = std::string(RAYFARM_TEST_OUT) + "/gpu_instancing";
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/" + test + "-" + name + ".gltf";
    std::ofstream(path) << g.dump();
    return path;
}

LoadedScene load(const json& g, const std::string& name) {
    DiskFileSource fs;
    SceneOptions o{};
    o.width = 100;
    o.height = 100;
    o.camera = 0;
    o.ground = Ground::None;  // no shadow catcher: only the cubes are hit
    return loadScene(writeFile(g, name), fs, o);
}

std::string refusal(const json& g) {
    try {
        load(g, "bad");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(loaded)";
}

/// Which pixels of the 100 x 100 picture see geometry (pixel centres), row by row, at time t of
/// the film (its timeline puts the file's camera in place and poses the nodes).
std::vector<uint8_t> covered(const LoadedScene& l, double t = 0.0) {
    Scene s = l.scene;
    Timeline::fromScene(l).apply(s, t);
    const CameraRays rays(s.camera, 100, 100);
    std::vector<uint8_t> hit(100 * 100, 0);
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 100; ++x) {
            Hit h;
            hit[size_t(y * 100 + x)] = s.geometry.intersect(rays.generate(x + 0.5f, y + 0.5f), h);
        }
    return hit;
}

/// The pixels whose centres lie in the axis-aligned rectangle [x0, x1] x [y0, y1] (world units,
/// y up, the picture's centre at the origin, 10 pixels a unit).
std::vector<uint8_t> rectangles(const std::vector<std::array<double, 4>>& rects) {
    std::vector<uint8_t> in(100 * 100, 0);
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 100; ++x) {
            const double wx = -5.0 + (x + 0.5) * 0.1, wy = 5.0 - (y + 0.5) * 0.1;
            for (const auto& r : rects) in[size_t(y * 100 + x)] |= wx > r[0] && wx < r[1] && wy > r[2] && wy < r[3];
        }
    return in;
}

/// Pixels where got and want differ; when some do, a diff image beside the test's files
/// (white: both cover it, red: only want, green: only got).
int differing(const std::vector<uint8_t>& got, const std::vector<uint8_t>& want, const std::string& name = "") {
    int n = 0;
    std::vector<uint8_t> rgb(got.size() * 3, 0);
    for (size_t i = 0; i < got.size(); ++i) {
        n += got[i] != want[i];
        rgb[3 * i] = want[i] ? 255 : 0;
        rgb[3 * i + 1] = got[i] ? 255 : 0;
        rgb[3 * i + 2] = got[i] && want[i] ? 255 : 0;
    }
    if (n) {
        const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        writePng(std::string(RAYFARM_TEST_OUT) + "/gpu_instancing/" + test + name + "-diff.png", 100, 100, rgb);
    }
    return n;
}

std::vector<Instance> threeCubes() {
    // (-3, -3) unit; (0, 0) stretched to 2 x 1; (3, 2) unit, a quarter turn about z (still a
    // unit square: the turn shows in the rotation being read, not in the coverage).
    const float quarter = float(std::sqrt(0.5));
    return {{{-3, -3, 0}, {0, 0, 0, 1}, {1, 1, 1}}, {{0, 0, 0}, {0, 0, 0, 1}, {2, 1, 1}}, {{3, 2, 0}, {0, 0, quarter, quarter}, {1, 1, 1}}};
}

}  // namespace

TEST(GpuInstancing, EachInstanceCoversTheSquareItsTransformGives) {
    const LoadedScene l = load(cubes(threeCubes()), "three");
    const std::vector<uint8_t> want = rectangles({{-3.5, -2.5, -3.5, -2.5}, {-1, 1, -0.5, 0.5}, {2.5, 3.5, 1.5, 2.5}});
    EXPECT_EQ(differing(covered(l), want), 0);
    // Without the extension the node draws its mesh once, at its own place.
    const LoadedScene plain = load(cubes({}), "plain");
    EXPECT_EQ(differing(covered(plain), rectangles({{-0.5, 0.5, -0.5, 0.5}}), "-plain"), 0);
}

TEST(GpuInstancing, RotationAndTheNodesTransformApply) {
    // A 2 x 1 box turned 30° counter-clockwise about z, under a node moved to (2, 1): the
    // rectangle |(p − c)·u| < 1, |(p − c)·v| < ½ with u = (cos 30°, sin 30°), v = (−sin 30°,
    // cos 30°). A turn the other way (or a quaternion read w-first) covers other pixels.
    const double a = M_PI / 6;
    json g = cubes({{{0, 0, 0}, {0, 0, float(std::sin(a / 2)), float(std::cos(a / 2))}, {2, 1, 1}}});
    g["nodes"][0]["translation"] = {2, 1, 0};
    auto rectangle = [&](double turn) {
        std::vector<uint8_t> want(100 * 100, 0);
        for (int y = 0; y < 100; ++y)
            for (int x = 0; x < 100; ++x) {
                const double dx = -5.0 + (x + 0.5) * 0.1 - 2.0, dy = 5.0 - (y + 0.5) * 0.1 - 1.0;
                const double along = dx * std::cos(turn) + dy * std::sin(turn), across = -dx * std::sin(turn) + dy * std::cos(turn);
                want[size_t(y * 100 + x)] = std::abs(along) < 1.0 && std::abs(across) < 0.5;
            }
        return want;
    };
    const std::vector<uint8_t> got = covered(load(g, "turned"));
    EXPECT_EQ(differing(got, rectangle(a)), 0);
    EXPECT_GT(differing(got, rectangle(-a), "-the-other-way"), 100);  // the check can tell the turns apart
}

TEST(GpuInstancing, AMirroringInstanceKeepsItsFrontFacesOutward) {
    // SCALE (−1, 1, 1) mirrors the cube: its triangles' corners are swapped back, so every
    // surface the camera sees faces it (geometric normal against the ray), as the unmirrored one.
    for (float sx : {1.f, -1.f}) {
        const LoadedScene l = load(cubes({{{0, 0, 0}, {0, 0, 0, 1}, {sx, 1, 1}}}), sx < 0 ? "mirrored" : "plain");
        Scene s = l.scene;
        Timeline::fromScene(l).apply(s, 0.0);
        const CameraRays rays(s.camera, 100, 100);
        int hits = 0, facing = 0;
        for (int y = 40; y < 60; ++y)
            for (int x = 40; x < 60; ++x) {
                Hit h;
                const Ray r = rays.generate(x + 0.5f, y + 0.5f);
                if (!s.geometry.intersect(r, h)) continue;
                ++hits;
                const SurfaceInteraction si = s.geometry.interaction(r, h);
                facing += glm::dot(si.ng, r.d) < 0.f && glm::dot(si.ns, r.d) < 0.f;
            }
        EXPECT_EQ(hits, 100) << "scale x " << sx;
        EXPECT_EQ(facing, hits) << "scale x " << sx;
    }
}

TEST(GpuInstancing, TheSizeCapCountsEveryInstance) {
    // 3,000,000 instances (a TRANSLATION accessor without a buffer view: zeros) of a 12-triangle
    // cube: 36 M triangles, over the 2^25 cap, refused before anything is read.
    json g = cubes(threeCubes());
    json& attrs = g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    g["accessors"].push_back({{"componentType", 5126}, {"count", 3000000}, {"type", "VEC3"}});
    attrs = {{"TRANSLATION", int(g["accessors"].size()) - 1}};
    EXPECT_NE(refusal(g).find("triangles once nodes instance their meshes"), std::string::npos) << refusal(g);
    // An application's own attribute alone gives the count: identity instances.
    json h = cubes(threeCubes());
    json& own = h["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
    own = {{"_ID", own["TRANSLATION"]}};
    const LoadedScene l = load(h, "ids");
    EXPECT_EQ(differing(covered(l), rectangles({{-0.5, 0.5, -0.5, 0.5}})), 0);
}

TEST(GpuInstancing, AnAnimatedNodeMovesEveryInstance) {
    const LoadedScene l = load(cubes(threeCubes(), true), "animated");
    for (double t : {0.0, 0.25, 0.75}) {  // (at 1 s the one-second clip starts over)
        const double dx = 2.0 * t;
        const std::vector<uint8_t> want =
            rectangles({{-3.5 + dx, -2.5 + dx, -3.5, -2.5}, {-1 + dx, 1 + dx, -0.5, 0.5}, {2.5 + dx, 3.5 + dx, 1.5, 2.5}});
        EXPECT_EQ(differing(covered(l, t), want, "-t" + std::to_string(t)), 0) << "at " << t << " s";
    }
}

TEST(GpuInstancing, InfoCountsTheInstances) {
    DiskFileSource fs;
    const GltfInfo info = inspectGltf(writeFile(cubes(threeCubes()), "info"), fs);
    ASSERT_EQ(info.meshes.size(), 1u);
    EXPECT_EQ(info.meshes[0].instances, 3u);
    EXPECT_EQ(info.meshes[0].gpuInstances, 3u);
    EXPECT_EQ(info.drawnTriangles, 36u);
}

TEST(GpuInstancing, ZeroScaleInstancesAreLeftOutWithANote) {
    std::vector<Instance> inst = threeCubes();
    inst[1].s[0] = 0;
    const LoadedScene l = load(cubes(inst), "zero");
    EXPECT_EQ(differing(covered(l), rectangles({{-3.5, -2.5, -3.5, -2.5}, {2.5, 3.5, 1.5, 2.5}})), 0);
    int notes = 0;
    for (const std::string& n : l.scene.notes) notes += n.find("1 EXT_mesh_gpu_instancing instances (per primitive) dropped") != std::string::npos;
    EXPECT_EQ(notes, 1);
}

TEST(GpuInstancing, MalformedInstancingIsRefusedNamingNodeAndAttribute) {
    json g = cubes(threeCubes());
    g["accessors"][g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"].get<int>()]["count"] = 2;
    EXPECT_NE(refusal(g).find("nodes[0].extensions.EXT_mesh_gpu_instancing.attributes.SCALE"), std::string::npos) << refusal(g);
    EXPECT_NE(refusal(g).find("2 instances, but TRANSLATION has 3"), std::string::npos) << refusal(g);
    g = cubes(threeCubes());
    g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["ROTATION"] =
        g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"];
    EXPECT_NE(refusal(g).find("attributes.ROTATION"), std::string::npos) << refusal(g);
    g = cubes(threeCubes());
    g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = json::object();
    EXPECT_NE(refusal(g).find("EXT_mesh_gpu_instancing: no attributes"), std::string::npos) << refusal(g);
    g = cubes(threeCubes());
    g["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] = 99;
    EXPECT_NE(refusal(g).find("attributes.TRANSLATION: no accessor 99"), std::string::npos) << refusal(g);
}

}  // namespace rf::anim
