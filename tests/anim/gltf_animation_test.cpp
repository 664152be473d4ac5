// glTF animations: sampler rules (case 26), node hierarchies, the hand-made scenes/animated_node.gltf
// with expected transforms worked out by hand, and real files from Debian's assimp-testmodels.
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "camera.h"
#include "errors.h"
#include "file_source.h"
#include "gltf_animation.h"
#include "scene_loader.h"
#include "timeline.h"

namespace rf::anim {
namespace {

const std::string kAssimp = "/usr/share/assimp/models/glTF2/";

std::string sourceFile(const std::string& rel) { return std::string(RAYFARM_SOURCE_DIR) + "/" + rel; }

/// Scratch directory for scenes the tests write (created on first use: tests run in any order).
std::string outDir() {
    const std::string d = std::string(RAYFARM_TEST_OUT) + "/anim";
    std::filesystem::create_directories(d);
    return d;
}

Scene load(const std::string& path) {
    DiskFileSource fs;
    return loadScene(path, fs);
}

/// Skips (with the reason) only when the build's glTF loader refuses glTF altogether.
#define LOAD_OR_SKIP(var, path)                                                                  \
    Scene var;                                                                                   \
    try {                                                                                        \
        var = load(path);                                                                        \
    } catch (const InputError& e) {                                                              \
        if (std::string(e.what()).find("not supported by this build") != std::string::npos)      \
            GTEST_SKIP() << "the glTF loader is not in this build: " << e.what();                \
        throw;                                                                                   \
    }

// Case 26: keys at 0 and 2 s, values 0 and 16, tangents 8 per second: v(0.5 s) = 4.0.
TEST(GltfSampler, CubicSplineTangentsAreScaledByTheKeyInterval) {
    AnimSampler s;
    s.interpolation = KeyInterpolation::CubicSpline;
    s.times = {0.f, 2.f};
    s.components = 1;
    s.values = {8.f, 0.f, 8.f, /* key 1: */ 8.f, 16.f, 8.f};  // in, value, out per key
    const KeyTrack w = trackFromSampler(s, AnimPath::Weights);
    EXPECT_DOUBLE_EQ(w.evaluateScalar(0.5), 4.0);  // unscaled tangents would give 3.25
    // The same on a translation (x carries the curve).
    s.components = 3;
    s.values = {8, 0, 0, 0, 0, 0, 8, 0, 0, /* key 1: */ 8, 0, 0, 16, 0, 0, 8, 0, 0};
    EXPECT_DOUBLE_EQ(trackFromSampler(s, AnimPath::Translation).evaluateVec3(0.5).x, 4.0);
}

TEST(GltfSampler, RejectsBadKeysAndCounts) {
    AnimSampler s;
    s.times = {0.f, 1.f, 1.f};
    s.values = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    try {
        trackFromSampler(s, AnimPath::Translation);
        FAIL() << "equal key times accepted";
    } catch (const KeyError& e) {
        EXPECT_EQ(e.key(), 2);
    }
    s.times = {0.f, 1.f};
    EXPECT_THROW(trackFromSampler(s, AnimPath::Translation), std::invalid_argument);  // 9 values for 2 keys
}

/// A two-node chain built in code: parent translation (LINEAR), child rotation (STEP).
SceneGraph chain() {
    SceneGraph g;
    g.source = "chain.gltf";
    g.nodes.resize(2);
    g.nodes[1].parent = 0;
    g.nodes[1].translation = DVec3(0, 0, 2);  // the child hangs 2 along the parent's z
    Animation a;
    AnimSampler tr;
    tr.times = {0.f, 1.f};
    tr.values = {0, 0, 0, 10, 0, 0};
    AnimSampler rot;
    rot.interpolation = KeyInterpolation::Step;
    rot.components = 4;
    rot.times = {0.f, 1.f};
    const float h = float(std::sqrt(0.5));
    rot.values = {0, 0, 0, 1, 0, h, 0, h};
    a.samplers = {tr, rot};
    a.channels = {{0, 0, AnimPath::Translation}, {1, 0, AnimPath::Rotation}};
    g.animations.push_back(a);
    return g;
}

TEST(GltfAnimation, ParentMotionCarriesTheChild) {
    const SceneGraph g = chain();
    const GltfAnimationPlayer p(g, 0, 0, false);
    std::vector<DMat4> m;
    std::vector<std::vector<double>> w;
    p.pose(g, 0.5, m, w);  // parent at (5, 0, 0), rotation still the first (identity) key
    EXPECT_NEAR(glm::length(DVec3(m[1][3]) - DVec3(5, 0, 2)), 0.0, 1e-12);
    p.pose(g, 1.0, m, w);  // parent at (10, 0, 0) turned 90° about y: its +z is world +x
    EXPECT_NEAR(glm::length(DVec3(m[1][3]) - DVec3(12, 0, 0)), 0.0, 1e-6);
    p.pose(g, 7.0, m, w);  // clamped
    EXPECT_NEAR(glm::length(DVec3(m[1][3]) - DVec3(12, 0, 0)), 0.0, 1e-6);
    const GltfAnimationPlayer looped(g, 0, 0, true);
    EXPECT_DOUBLE_EQ(looped.localTime(2.25), 0.25);
    EXPECT_DOUBLE_EQ(looped.localTime(-0.25), 0.75);
}

TEST(GltfAnimation, MatrixNodesCannotBeAnimated) {
    SceneGraph g = chain();
    g.nodes[0].useMatrix = true;
    try {
        GltfAnimationPlayer p(g, 0, 0, true);
        FAIL() << "accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("chain.gltf: animations[0].channels[0]: animates node 0, which has a matrix"), std::string::npos) << e.what();
    }
}

/// scenes/animated_node.gltf, worked out by hand. "carrier" (node 0) translates by a CUBICSPLINE
/// over 0..2 s from (0,0,0) (out-tangent (0,4,0)/s) to (4,0,0) (in-tangent (0,−4,0)/s); with
/// h10 = u(1−u)², h01 = u²(3−2u), h11 = u²(u−1) and the 2 s interval:
///   t = 0.5: (0.625, 1.5, 0)   t = 1: (2, 2, 0)   t = 1.5: (3.375, 1.5, 0)
/// "cube" (node 1, the mesh) turns about y by LINEAR keys 0°, 90°, 180° at 0, 1, 2 s (the last
/// stored as −q, which the short path must honour): 45°, 90°, 135° at the times above. Its
/// scale is STEP: (1,1,1) until 1 s, then (2, 0.5, 1).
DMat4 expectedCube(double t) {
    struct P {
        double t;
        DVec3 tr;
        double deg;
        DVec3 sc;
    } table[] = {{0.5, {0.625, 1.5, 0}, 45, {1, 1, 1}}, {1.0, {2, 2, 0}, 90, {2, 0.5, 1}}, {1.5, {3.375, 1.5, 0}, 135, {2, 0.5, 1}}};
    for (const P& p : table)
        if (p.t == t)
            return glm::scale(glm::rotate(glm::translate(DMat4(1.0), p.tr), glm::radians(p.deg), DVec3(0, 1, 0)), p.sc);
    ADD_FAILURE() << "no hand-computed pose at " << t;
    return DMat4(1.0);
}

void expectMeshAt(const Scene& s, const DMat4& worldFromNode, const std::string& where) {
    int moved = 0;
    for (const TriangleMesh& m : s.meshes) {
        if (m.node < 0) continue;
        ++moved;
        ASSERT_EQ(m.objectPositions.size(), m.positions.size());
        for (size_t i = 0; i < m.positions.size(); ++i) {
            const DVec3 o(m.objectPositions[i]);
            ASSERT_EQ(glm::abs(o), DVec3(0.5)) << "the file's cube corners are at ±0.5";
            const DVec3 want = DVec3(worldFromNode * glm::dvec4(o, 1.0)) - s.renderOrigin;
            EXPECT_NEAR(glm::length(DVec3(m.positions[i]) - want), 0.0, 1e-5) << where << " vertex " << i;
        }
    }
    EXPECT_EQ(moved, 1) << where;
}

TEST(AnimatedNodeGltf, NodeTransformsMatchTheHandComputedPoses) {
    LOAD_OR_SKIP(s, sourceFile("scenes/animated_node.gltf"));
    ASSERT_EQ(s.models.size(), 1u);
    ASSERT_EQ(s.models[0].animations.size(), 2u);
    // A bare model gets the default turntable (120 frames) and plays its first animation, looped.
    const Timeline tl = Timeline::fromScene(s);
    EXPECT_EQ(tl.frameCount(), 120);
    EXPECT_TRUE(tl.animatesGeometry());
    for (double t : {0.5, 1.0, 1.5}) {
        tl.apply(s, t);
        expectMeshAt(s, expectedCube(t), "t = " + std::to_string(t));
        tl.apply(s, t + 2.0);  // one loop later: the same pose
        expectMeshAt(s, expectedCube(t), "t = " + std::to_string(t) + " + 2 s");
    }
    // The hierarchy itself, from the player.
    const GltfAnimationPlayer p(s.models[0], 0, 0, true);
    std::vector<DMat4> m;
    std::vector<std::vector<double>> w;
    p.pose(s.models[0], 1.0, m, w);
    EXPECT_NEAR(glm::length(DVec3(m[0][3]) + s.renderOrigin - DVec3(2, 2, 0)), 0.0, 1e-6);
    // STEP holds until its next key.
    p.pose(s.models[0], 0.999, m, w);
    EXPECT_NEAR(glm::length(DVec3(m[1][0])), 1.0, 1e-6);
    p.pose(s.models[0], 1.0, m, w);
    EXPECT_NEAR(glm::length(DVec3(m[1][0])), 2.0, 1e-6);
}

// The default turntable frames the bounds the animation sweeps, not only the rest pose: the
// cube stays in the picture while it travels to x = 4 and back.
TEST(AnimatedNodeGltf, DefaultTurntableKeepsTheMovingModelInView) {
    LOAD_OR_SKIP(s, sourceFile("scenes/animated_node.gltf"));
    const Timeline tl = Timeline::fromScene(s);
    for (int f = 0; f < tl.frameCount(); f += 5) {
        tl.applyFrame(s, f);
        const CameraRays cam(s.camera, s.settings.width, s.settings.height);
        for (const TriangleMesh& m : s.meshes)
            for (const Vec3& p : m.positions) {
                const Vec3 d = p - cam.origin;
                const float z = glm::dot(d, cam.basis.forward);
                ASSERT_GT(z, 0.f) << "frame " << f << ": a vertex is behind the camera";
                EXPECT_LE(std::abs(glm::dot(d, cam.basis.right) / z), std::abs(cam.tanHalfX)) << "frame " << f;
                EXPECT_LE(std::abs(glm::dot(d, cam.basis.up) / z), std::abs(cam.tanHalfY)) << "frame " << f;
            }
    }
}

// `rayfarm render --fps` writes {"turntable": {"fps": N}} into a bare model's timeline: that
// must be the default turntable at another rate, not a different preset.
TEST(AnimatedNodeGltf, ExplicitTurntableOnABareModelKeepsTheModelDefaults) {
    LOAD_OR_SKIP(s, sourceFile("scenes/animated_node.gltf"));
    ASSERT_FALSE(s.lights.empty());
    Scene a = s, b = s;
    b.timeline = std::make_shared<const nlohmann::json>(nlohmann::json::parse(R"({"turntable": {"fps": 30}})"));
    const Timeline ta = Timeline::fromScene(a), tb = Timeline::fromScene(b);
    ASSERT_EQ(ta.frameCount(), tb.frameCount());
    ta.applyFrame(a, 10);
    tb.applyFrame(b, 10);
    EXPECT_EQ(a.camera.eye, b.camera.eye);
    for (size_t i = 0; i < a.lights.size(); ++i) EXPECT_EQ(a.lights[i].position, b.lights[i].position) << "light " << i;
    // And the lights did follow the camera (they moved from their loaded place).
    EXPECT_NE(a.lights[0].position, s.lights[0].position);
}

TEST(AnimatedNodeGltf, AnimationSelectedByNameClampsAndRefitsTheBvh) {
    const std::string path = outDir() + "/lift.json";
    std::ofstream(path) << R"({"camera": {"eye": [0, 1, 10], "target": [0, 1, 0]},
      "objects": [{"type": "model", "path": ")" << sourceFile("scenes/animated_node.gltf") << R"("}],
      "timeline": {"fps": 10, "duration": 2, "animation": {"name": "lift", "mode": "clamp"}}})";
    LOAD_OR_SKIP(s, path);
    const Timeline tl = Timeline::fromScene(s);
    EXPECT_EQ(tl.frameCount(), 21);
    tl.apply(s, 5.0);  // clamped at the end of "lift": carrier at (0, 3, 0), cube at rest
    expectMeshAt(s, glm::translate(DMat4(1.0), DVec3(0, 3, 0)), "lift, clamped");
    // Traversal sees the moved cube (the BVH was refitted), and not its old place.
    const Vec3 o = Vec3(DVec3(0, 3, 10) - s.renderOrigin);
    Hit hit;
    EXPECT_TRUE(s.intersect(Ray(o, Vec3(0, 0, -1)), hit));
    EXPECT_NEAR(hit.t, 9.5f, 1e-4f);
    Hit miss;
    EXPECT_FALSE(s.intersect(Ray(Vec3(DVec3(0, 0, 10) - s.renderOrigin), Vec3(0, 0, -1)), miss));
    tl.apply(s, 0.5);
    expectMeshAt(s, glm::translate(DMat4(1.0), DVec3(0, 1.5, 0)), "lift at 0.5 s");

    std::ofstream(path) << R"({"objects": [{"type": "model", "path": ")" << sourceFile("scenes/animated_node.gltf") << R"("}],
      "timeline": {"animation": {"name": "dance"}}})";
    try {
        Timeline::fromScene(load(path));
        FAIL() << "unknown animation accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("timeline.animation.name: the model has no animation named \"dance\""), std::string::npos) << e.what();
    }
}

TEST(GltfAnimation, StaticModelsDoNotPayForAnimation) {
    LOAD_OR_SKIP(s, kAssimp + "BoxTextured-glTF/BoxTextured.gltf");
    for (const TriangleMesh& m : s.meshes) EXPECT_LT(m.node, 0);
    const Timeline tl = Timeline::fromScene(s);
    EXPECT_FALSE(tl.animatesGeometry());
    EXPECT_EQ(tl.frameCount(), 120);  // still a turntable
    // An animated model told not to play does not pay either.
    const std::string path = outDir() + "/still_model.json";
    std::ofstream(path) << R"({"objects": [{"type": "model", "path": ")" << sourceFile("scenes/animated_node.gltf") << R"("}],
      "timeline": {"animation": false}})";
    LOAD_OR_SKIP(a, path);
    EXPECT_FALSE(Timeline::fromScene(a).animatesGeometry());
}

// Khronos' AnimatedMorphCube: one node (rotation, scale 100) whose two morph weights follow a
// LINEAR sampler of 127 keys.
TEST(RealGltf, AnimatedMorphCubeWeightsMoveTheVertices) {
    LOAD_OR_SKIP(s, kAssimp + "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
    ASSERT_EQ(s.models.size(), 1u);
    ASSERT_EQ(s.models[0].animations.size(), 1u);
    const Animation& an = s.models[0].animations[0];
    ASSERT_EQ(an.channels.size(), 1u);
    ASSERT_EQ(an.channels[0].path, AnimPath::Weights);
    const AnimSampler& smp = an.samplers[0];
    ASSERT_EQ(smp.times.size(), 127u);
    ASSERT_EQ(smp.components, 2);
    const Timeline tl = Timeline::fromScene(s);
    ASSERT_TRUE(tl.animatesGeometry());
    // The node's matrix, typed from the file: rotation (0, 0.7071067, −0.7071068, 0), scale 100.
    const DMat4 node = glm::scale(glm::mat4_cast(glm::normalize(DQuat(0.0, 0.0, 0.7071067, -0.7071068))), DVec3(100.0));
    auto check = [&](double t, double w0, double w1, const std::string& where) {
        tl.apply(s, t);
        int n = 0;
        for (const TriangleMesh& m : s.meshes) {
            if (m.node < 0) continue;
            ASSERT_EQ(m.morphPositions.size(), 2u);
            for (size_t i = 0; i < m.positions.size(); ++i, ++n) {
                const DVec3 obj = DVec3(m.objectPositions[i]) + w0 * DVec3(m.morphPositions[0][i]) + w1 * DVec3(m.morphPositions[1][i]);
                const DVec3 want = DVec3(s.models[0].renderFromModel * node * glm::dvec4(obj, 1.0));
                ASSERT_NEAR(glm::length(DVec3(m.positions[i]) - want), 0.0, 1e-4) << where << " vertex " << i;
            }
        }
        EXPECT_GT(n, 0);
    };
    // Exactly at a key: that key's weights. Between two keys: their linear blend.
    const size_t k = 40;
    const double tk = smp.times[k], tk1 = smp.times[k + 1];
    check(tk, smp.values[2 * k], smp.values[2 * k + 1], "at key 40");
    const double u = 0.3, tm = tk + u * (tk1 - tk);
    check(tm, smp.values[2 * k] + u * (smp.values[2 * k + 2] - smp.values[2 * k]),
          smp.values[2 * k + 1] + u * (smp.values[2 * k + 3] - smp.values[2 * k + 1]), "between keys 40 and 41");
    // And the shape really changes over the animation (weights are not all equal).
    tl.apply(s, 0.0);
    const Aabb b0 = s.bounds();
    tl.apply(s, smp.times[63]);
    const Aabb b1 = s.bounds();
    EXPECT_GT(glm::length(b1.extent() - b0.extent()), 1e-3f);
}

// simple_skin animates a joint; skins are not supported, and the loader says so: the skinned
// mesh stays in its bind pose while the joint's animation still evaluates without harm.
TEST(RealGltf, SimpleSkinIsRefusedClearly) {
    LOAD_OR_SKIP(s, kAssimp + "simple_skin/simple_skin.gltf");
    bool noted = false;
    for (const std::string& n : s.notes) noted |= n.find("skins are not supported") != std::string::npos;
    EXPECT_TRUE(noted) << "no note about the unsupported skin";
    ASSERT_EQ(s.models.size(), 1u);
    ASSERT_EQ(s.models[0].animations.size(), 1u);
    const Timeline tl = Timeline::fromScene(s);
    Scene a = s, b = s;
    tl.apply(a, 0.0);
    tl.apply(b, 1.0);
    ASSERT_EQ(a.meshes.size(), b.meshes.size());
    for (size_t m = 0; m < a.meshes.size(); ++m) EXPECT_EQ(a.meshes[m].positions, b.meshes[m].positions);
}

}  // namespace
}  // namespace rf::anim
