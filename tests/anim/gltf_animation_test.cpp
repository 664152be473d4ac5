// glTF animations: sampler rules (case 26), node hierarchies, the hand-made scenes/animated_node.gltf
// with expected transforms worked out by hand, and real files from Debian's assimp-testmodels.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>

#include <nlohmann/json.hpp>
#include <fstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/geometry/camera.h"
#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "anim/gltf_animation.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"

namespace rf::anim {
namespace {

const std::string kAssimp = "/usr/share/assimp/models/glTF2/";

std::string sourceFile(const std::string& rel) { return std::string(RAYFARM_SOURCE_DIR) + "/" + rel; }

/// Scratch directory for scenes the tests write (created on first use: tests run in any order).
std::string outDir() {
    std::string d = RAYFARM_TEST_OUT;  // appended, not operator+: GCC 12 warns falsely under LTO
    d += "/anim";
    std::filesystem::create_directories(d);
    return d;
}

LoadedScene load(const std::string& path) {
    DiskFileSource fs;
    return loadScene(path, fs);
}

/// Skips (with the reason) only when the build's glTF loader refuses glTF altogether.
/// Declares var##Loaded (the LoadedScene) and var, its scene.
#define LOAD_OR_SKIP(var, path)                                                                  \
    LoadedScene var##Loaded;                                                                     \
    try {                                                                                        \
        var##Loaded = load(path);                                                                \
    } catch (const InputError& e) {                                                              \
        if (std::string(e.what()).find("not supported by this build") != std::string::npos)      \
            GTEST_SKIP() << "the glTF loader is not in this build: " << e.what();                \
        throw;                                                                                   \
    }                                                                                            \
    [[maybe_unused]] Scene& var = var##Loaded.scene

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

/// The message of the InputError a player of g throws ("" if none).
std::string playerError(const SceneGraph& g) {
    try {
        GltfAnimationPlayer p(g, 0, 0, true);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// Issue 30 #9: a zero quaternion was reported at samplers[1].input[1], the key's time, which is
// fine; the fault is in the output accessor, at the key's element (CUBICSPLINE: in-tangent,
// value, out-tangent per key, so key k's value is element 3k + 1).
TEST(GltfAnimation, AKeysFaultIsNamedInTheAccessorThatHoldsIt) {
    SceneGraph g = chain();
    AnimSampler& rot = g.animations[0].samplers[1];
    rot.values = {0, 0, 0, 1, 0, 0, 0, 0};
    EXPECT_EQ(playerError(g), "chain.gltf: animations[0].samplers[1].output[1]: a rotation quaternion must not be zero");
    rot.interpolation = KeyInterpolation::CubicSpline;
    rot.values = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, /* key 1: */ 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ(playerError(g), "chain.gltf: animations[0].samplers[1].output[4]: a rotation quaternion must not be zero");
    rot.values[13] = 1.f;  // key 1's in-tangent: non-finite below
    rot.values[16] = 1.f;  // its value
    rot.values[20] = std::numeric_limits<float>::infinity();  // its out-tangent
    EXPECT_EQ(playerError(g), "chain.gltf: animations[0].samplers[1].output[5]: expected finite tangents");
    rot.values[20] = 0.f;
    rot.times = {1.f, 1.f};
    EXPECT_NE(playerError(g).find("chain.gltf: animations[0].samplers[1].input[1]: times must increase"), std::string::npos) << playerError(g);
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
    for (const TriangleMesh& m : s.geometry.meshes) {
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
    ASSERT_EQ(s.geometry.models.size(), 1u);
    ASSERT_EQ(s.geometry.models[0].animations.size(), 2u);
    // A bare model gets the default turntable (120 frames) and plays its first animation, looped.
    const Timeline tl = Timeline::fromScene(sLoaded);
    EXPECT_EQ(tl.frameCount(), 120);
    EXPECT_TRUE(tl.animatesGeometry());
    for (double t : {0.5, 1.0, 1.5}) {
        tl.apply(s, t);
        expectMeshAt(s, expectedCube(t), "t = " + std::to_string(t));
        tl.apply(s, t + 2.0);  // one loop later: the same pose
        expectMeshAt(s, expectedCube(t), "t = " + std::to_string(t) + " + 2 s");
    }
    // The hierarchy itself, from the player.
    const GltfAnimationPlayer p(s.geometry.models[0], 0, 0, true);
    std::vector<DMat4> m;
    std::vector<std::vector<double>> w;
    p.pose(s.geometry.models[0], 1.0, m, w);
    EXPECT_NEAR(glm::length(DVec3(m[0][3]) + s.renderOrigin - DVec3(2, 2, 0)), 0.0, 1e-6);
    // STEP holds until its next key.
    p.pose(s.geometry.models[0], 0.999, m, w);
    EXPECT_NEAR(glm::length(DVec3(m[1][0])), 1.0, 1e-6);
    p.pose(s.geometry.models[0], 1.0, m, w);
    EXPECT_NEAR(glm::length(DVec3(m[1][0])), 2.0, 1e-6);
}

// The default turntable frames the bounds the animation sweeps, not only the rest pose: the
// cube stays in the picture while it travels to x = 4 and back.
TEST(AnimatedNodeGltf, DefaultTurntableKeepsTheMovingModelInView) {
    LOAD_OR_SKIP(s, sourceFile("scenes/animated_node.gltf"));
    const Timeline tl = Timeline::fromScene(sLoaded);
    for (int f = 0; f < tl.frameCount(); f += 5) {
        tl.applyFrame(s, f);
        const CameraRays cam(s.camera, s.settings.width, s.settings.height);
        for (const TriangleMesh& m : s.geometry.meshes)
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
    TimelineSource turntable;
    turntable.sections = std::make_shared<const nlohmann::json>(nlohmann::json::parse(R"({"turntable": {"fps": 30}})"));
    const Timeline ta = Timeline::fromScene(a, sLoaded.timeline), tb = Timeline::fromScene(b, turntable);
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
    const Timeline tl = Timeline::fromScene(sLoaded);
    EXPECT_EQ(tl.frameCount(), 21);
    tl.apply(s, 5.0);  // clamped at the end of "lift": carrier at (0, 3, 0), cube at rest
    expectMeshAt(s, glm::translate(DMat4(1.0), DVec3(0, 3, 0)), "lift, clamped");
    // Traversal sees the moved cube (the BVH was refitted), and not its old place.
    const Vec3 o = Vec3(DVec3(0, 3, 10) - s.renderOrigin);
    Hit hit;
    // Braces, not parentheses: clang before 16 has no parenthesized aggregate initialization.
    const Ray down{o, Vec3(0, 0, -1)};
    EXPECT_TRUE(s.geometry.intersect(down, hit));
    EXPECT_NEAR(hit.t, 9.5f, 1e-4f);
    Hit miss;
    const Ray oldPlace{Vec3(DVec3(0, 0, 10) - s.renderOrigin), Vec3(0, 0, -1)};
    EXPECT_FALSE(s.geometry.intersect(oldPlace, miss));
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
    for (const TriangleMesh& m : s.geometry.meshes) EXPECT_LT(m.node, 0);
    const Timeline tl = Timeline::fromScene(sLoaded);
    EXPECT_FALSE(tl.animatesGeometry());
    EXPECT_EQ(tl.frameCount(), 120);  // still a turntable
    // An animated model told not to play does not pay either.
    const std::string path = outDir() + "/still_model.json";
    std::ofstream(path) << R"({"objects": [{"type": "model", "path": ")" << sourceFile("scenes/animated_node.gltf") << R"("}],
      "timeline": {"animation": false}})";
    EXPECT_FALSE(Timeline::fromScene(load(path)).animatesGeometry());
}

// Khronos' AnimatedMorphCube: one node (rotation, scale 100) whose two morph weights follow a
// LINEAR sampler of 127 keys.
TEST(RealGltf, AnimatedMorphCubeWeightsMoveTheVertices) {
    LOAD_OR_SKIP(s, kAssimp + "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
    ASSERT_EQ(s.geometry.models.size(), 1u);
    ASSERT_EQ(s.geometry.models[0].animations.size(), 1u);
    const Animation& an = s.geometry.models[0].animations[0];
    ASSERT_EQ(an.channels.size(), 1u);
    ASSERT_EQ(an.channels[0].path, AnimPath::Weights);
    const AnimSampler& smp = an.samplers[0];
    ASSERT_EQ(smp.times.size(), 127u);
    ASSERT_EQ(smp.components, 2);
    const Timeline tl = Timeline::fromScene(sLoaded);
    ASSERT_TRUE(tl.animatesGeometry());
    // The node's matrix, typed from the file: rotation (0, 0.7071067, −0.7071068, 0), scale 100.
    const DMat4 node = glm::scale(glm::mat4_cast(glm::normalize(DQuat(0.0, 0.0, 0.7071067, -0.7071068))), DVec3(100.0));
    auto check = [&](double t, double w0, double w1, const std::string& where) {
        tl.apply(s, t);
        int n = 0;
        for (const TriangleMesh& m : s.geometry.meshes) {
            if (m.node < 0) continue;
            ASSERT_EQ(m.morphPositions.size(), 2u);
            for (size_t i = 0; i < m.positions.size(); ++i, ++n) {
                const DVec3 obj = DVec3(m.objectPositions[i]) + w0 * DVec3(m.morphPositions[0][i]) + w1 * DVec3(m.morphPositions[1][i]);
                const DVec3 want = DVec3(s.geometry.models[0].renderFromModel * node * glm::dvec4(obj, 1.0));
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
    const Aabb b0 = s.geometry.bounds();
    tl.apply(s, smp.times[63]);
    const Aabb b1 = s.geometry.bounds();
    EXPECT_GT(glm::length(b1.extent() - b0.extent()), 1e-3f);
}

// simple_skin (the glTF tutorial's skin): ten vertices (x ∈ {0, 1}, y ∈ {0, .5, 1, 1.5, 2}) on
// joints node 1 (translate(0, 1, 0)) and its child node 2, whose rotation about z is animated
// (0° at 0 s, 90° at 1 s, −90° at 4 s). Both inverse bind matrices are translate(−0.5, −1, 0) and
// row y has weights (1 − y/2, y/2). Worked out by hand from the file's JSON:
// p(θ) = a·(x − .5, y) + (1 − a)·[(0, 1) + R(θ)·(x − .5, y − 1)], a = 1 − y/2.
std::vector<glm::dvec3> simpleSkinExpected(double thetaDeg) {
    std::vector<glm::dvec3> out;
    const double th = glm::radians(thetaDeg), c = std::cos(th), sn = std::sin(th);
    for (int row = 0; row < 5; ++row)
        for (int x = 0; x < 2; ++x) {
            const double y = 0.5 * row, a = 1.0 - y / 2.0;
            const glm::dvec2 j1(x - 0.5, y), d(x - 0.5, y - 1.0);
            const glm::dvec2 j2 = glm::dvec2(0.0, 1.0) + glm::dvec2(c * d.x - sn * d.y, sn * d.x + c * d.y);
            const glm::dvec2 p = a * j1 + (1.0 - a) * j2;
            out.push_back(glm::dvec3(p, 0.0));
        }
    return out;
}

TEST(RealGltf, SimpleSkinIsPosedByItsAnimatedJoint) {
    LOAD_OR_SKIP(s, kAssimp + "simple_skin/simple_skin.gltf");
    for (const std::string& n : s.notes) EXPECT_EQ(n.find("skins are not supported"), std::string::npos) << n;
    ASSERT_EQ(s.geometry.models.size(), 1u);
    ASSERT_EQ(s.geometry.models[0].skins.size(), 1u);
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    const Timeline tl = Timeline::fromScene(sLoaded);
    EXPECT_TRUE(tl.animatesGeometry());
    for (const auto& [t, theta] : std::vector<std::pair<double, double>>{{0.0, 0.0}, {1.0, 90.0}, {4.0, -90.0}, {0.5, 45.0}}) {
        Scene a = s;
        tl.apply(a, t);
        const std::vector<glm::dvec3> e = simpleSkinExpected(theta);
        ASSERT_EQ(a.geometry.meshes[0].positions.size(), e.size());
        for (size_t i = 0; i < e.size(); ++i) {
            const glm::dvec3 p = glm::dvec3(a.geometry.meshes[0].positions[i]) + a.renderOrigin;
            // 45° at 0.5 s is the file's key (0.383, 0.924), 45.03°: 1e-3 covers it.
            EXPECT_NEAR(glm::length(p - e[i]), 0.0, theta == 45.0 ? 1e-3 : 1e-5) << "t " << t << " vertex " << i;
        }
    }
}

/// Pixel position of a world point through a camera (CameraRays::generate inverted).
glm::dvec2 project(const CameraRays& cr, const glm::dvec3& p) {
    const glm::dvec3 v = p - glm::dvec3(cr.origin);
    const double z = glm::dot(v, glm::dvec3(cr.basis.forward));
    const double sx = glm::dot(v, glm::dvec3(cr.basis.right)) / z / cr.tanHalfX;
    const double sy = glm::dot(v, glm::dvec3(cr.basis.up)) / z / cr.tanHalfY;
    return {(sx + 1.0) * cr.width / 2.0, (1.0 - sy) * cr.height / 2.0};
}

bool insideTriangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
    auto edge = [](const glm::dvec2& u, const glm::dvec2& v, const glm::dvec2& q) { return (v.x - u.x) * (q.y - u.y) - (v.y - u.y) * (q.x - u.x); };
    const double e0 = edge(a, b, p), e1 = edge(b, c, p), e2 = edge(c, a, p);
    return (e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0);
}

// The picture: the rendered silhouette (coverage of a transparent background) against the
// hand-worked posed strip rasterized here, at 0 s and 1 s; and the two poses differ.
TEST(RealGltf, SimpleSkinSilhouetteFollowsThePose) {
    LOAD_OR_SKIP(s, kAssimp + "simple_skin/simple_skin.gltf");
    const Timeline tl = Timeline::fromScene(sLoaded);
    const int W = 160, H = 160;
    std::vector<std::vector<uint8_t>> masks;
    for (const auto& [t, theta] : std::vector<std::pair<double, double>>{{0.0, 0.0}, {1.0, 90.0}}) {
        Scene a = s;
        tl.apply(a, t);
        a.transparentBackground = true;
        Camera cam;  // a fixed camera facing the strip's plane (the turntable's would turn edge-on)
        cam.eye = Vec3(glm::dvec3(0.0, 1.0, 6.0) - a.renderOrigin);
        cam.target = Vec3(glm::dvec3(0.0, 1.0, 0.0) - a.renderOrigin);
        cam.fovDeg = 45.f;
        RenderSettings rs = a.settings;
        rs.width = W, rs.height = H, rs.spp = 1;
        RayStats stats;
        const Image img = renderFrame(a, {cam, rs}, 0, 1, stats);
        ASSERT_TRUE(img.hasAlpha());
        const CameraRays cr(cam, W, H);
        const std::vector<glm::dvec3> e = simpleSkinExpected(theta);
        std::vector<glm::dvec2> q;
        for (const glm::dvec3& p : e) q.push_back(project(cr, p - a.renderOrigin));
        const int quads[4][4] = {{0, 1, 3, 2}, {2, 3, 5, 4}, {4, 5, 7, 6}, {6, 7, 9, 8}};
        size_t both = 0, either = 0;
        std::vector<uint8_t> diff(size_t(W) * H * 3, 0), mask(size_t(W) * H, 0);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const glm::dvec2 c(x + 0.5, y + 0.5);
                bool expect = false;
                for (const auto& k : quads)
                    expect |= insideTriangle(c, q[k[0]], q[k[1]], q[k[2]]) || insideTriangle(c, q[k[0]], q[k[2]], q[k[3]]);
                const bool got = img.alpha()[size_t(y) * W + x] > 0.5f;
                mask[size_t(y) * W + x] = got;
                both += expect && got;
                either += expect || got;
                uint8_t* d = &diff[3 * (size_t(y) * W + x)];
                d[0] = got && !expect ? 255 : 0, d[1] = got && expect ? 255 : 0, d[2] = expect && !got ? 255 : 0;
            }
        ASSERT_GT(either, 500u) << "the strip covers almost nothing";
        const double iou = double(both) / double(either);
        // The edges run through pixels whose centres fall either way: 0.97 leaves one pixel's rim.
        if (iou < 0.97) writePng(outDir() + "/simple_skin_t" + std::to_string(int(t)) + "_diff.png", W, H, diff);
        EXPECT_GE(iou, 0.97) << "t " << t << ": silhouette IoU against the hand-posed strip";
        masks.push_back(mask);
    }
    size_t changed = 0, covered = 0;
    for (size_t i = 0; i < masks[0].size(); ++i) changed += masks[0][i] != masks[1][i], covered += masks[0][i];
    // The upper half turns 90° about the middle: over half the strip's pixels change.
    EXPECT_GT(changed, covered * 3 / 10) << "the pose at 1 s looks like the pose at 0 s";
}

}  // namespace
}  // namespace rf::anim

namespace rf::anim {
namespace {

LoadedScene loadWith(const std::string& path, const std::string& animation) {
    DiskFileSource fs;
    SceneOptions o;
    o.animation = animation;
    return loadScene(path, fs, o);
}

/// Vertex positions of every mesh of s posed at t by its timeline.
std::vector<std::vector<Vec3>> posedAt(LoadedScene loaded, double t) {
    Scene& s = loaded.scene;
    Timeline::fromScene(loaded).apply(s, t);
    std::vector<std::vector<Vec3>> out;
    for (const TriangleMesh& m : s.geometry.meshes) out.push_back(m.positions);
    return out;
}

// scenes/animated_node.gltf has "move" (2 s) and "lift" (1 s, node 0's translation only).
TEST(AnimationChoice, ByNameOrIndexPlaysThatClip) {
    const std::string model = sourceFile("scenes/animated_node.gltf");
    const LoadedScene first = load(model), lift = loadWith(model, "lift"), one = loadWith(model, "1"), zero = loadWith(model, "0");
    EXPECT_EQ(posedAt(lift, 0.5), posedAt(one, 0.5));
    EXPECT_EQ(posedAt(first, 0.5), posedAt(zero, 0.5));  // the default stays the first
    EXPECT_NE(posedAt(first, 0.5), posedAt(lift, 0.5));
}

TEST(AnimationChoice, AnUnknownNameIsRefusedListingTheFilesAnimations) {
    const std::string model = sourceFile("scenes/animated_node.gltf");
    for (const std::string& bad : {std::string("run"), std::string("2")}) {
        try {
            Timeline::fromScene(loadWith(model, bad));
            FAIL() << bad << " accepted";
        } catch (const InputError& e) {
            const std::string m = e.what();
            const std::string what = bad == "2" ? "no animation 2" : "no animation named \"run\"";
            EXPECT_NE(m.find("--animation: " + what + " (animated_node.gltf has 2: 0 \"move\", 1 \"lift\")"), std::string::npos) << m;
        }
    }
    // A model without animations says so.
    try {
        Timeline::fromScene(loadWith(kAssimp + "BoxTextured-glTF/BoxTextured.gltf", "walk"));
        FAIL() << "an animation chosen on a model without any";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("BoxTextured.gltf has no animations"), std::string::npos) << e.what();
    }
}

TEST(AnimationChoice, TheSceneFileKeyNamesAClipAndTheCommandLineWins) {
    const std::string model = sourceFile("scenes/animated_node.gltf");
    const std::string path = outDir() + "/choose_lift.json";
    std::ofstream(path) << R"({"objects": [{"type": "model", "path": ")" << model << R"("}],
      "turntable": {"animation": "lift"}})";
    // The key plays lift, exactly as --animation lift does, and not the first clip.
    const LoadedScene byKey = load(path);
    const std::string cliPath = outDir() + "/choose_default.json";
    std::ofstream(cliPath) << R"({"objects": [{"type": "model", "path": ")" << model << R"("}], "turntable": {}})";
    EXPECT_EQ(posedAt(byKey, 0.5), posedAt(loadWith(cliPath, "lift"), 0.5));
    EXPECT_NE(posedAt(byKey, 0.5), posedAt(load(cliPath), 0.5));
    const std::string bad = outDir() + "/choose_bad.json";
    std::ofstream(bad) << R"({"objects": [{"type": "model", "path": ")" << model << R"("}],
      "turntable": {"animation": "nope"}})";
    try {
        Timeline::fromScene(load(bad));
        FAIL() << "an unknown name in the scene file accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("choose_bad.json: turntable.animation: no animation named \"nope\""), std::string::npos) << e.what();
    }
    // --animation overrides the key: the bad file renders with the command line's choice.
    DiskFileSource fs;
    SceneOptions o;
    o.animation = "move";
    const LoadedScene overridden = loadScene(bad, fs, o);
    EXPECT_NO_THROW(Timeline::fromScene(overridden));
}

// The film-length rule (docs/cli.md#animations): one orbit over the fewest whole plays of the
// clip lasting at least 4 s.
TEST(AnimationChoice, ABareModelsFilmLastsWholePlaysOfItsClip) {
    EXPECT_DOUBLE_EQ(filmSecondsForClip(1.0, 4.0), 4.0);
    EXPECT_DOUBLE_EQ(filmSecondsForClip(2.5, 4.0), 5.0);
    EXPECT_DOUBLE_EQ(filmSecondsForClip(5.5, 4.0), 5.5);
    EXPECT_DOUBLE_EQ(filmSecondsForClip(0.0, 4.0), 4.0);
    EXPECT_DOUBLE_EQ(filmSecondsForClip(7200.0, 4.0), 4.0);
    LOAD_OR_SKIP(skin, kAssimp + "simple_skin/simple_skin.gltf");  // a 5.5 s clip
    EXPECT_EQ(Timeline::fromScene(skinLoaded).frameCount(), 165);
    LOAD_OR_SKIP(box, kAssimp + "BoxTextured-glTF/BoxTextured.gltf");  // no animation
    EXPECT_EQ(Timeline::fromScene(boxLoaded).frameCount(), 120);
    // A turntable section without seconds plays "move" (2 s) at speed 0.6: 3⅓ s a play, two plays.
    const std::string path = outDir() + "/slow_move.json";
    std::ofstream(path) << R"({"objects": [{"type": "model", "path": ")" << sourceFile("scenes/animated_node.gltf")
                        << R"("}], "turntable": {"animation": {"name": "move", "speed": 0.6}}})";
    const Timeline slow = Timeline::fromScene(load(path));
    EXPECT_EQ(slow.frameCount(), 200);
    // The clip and the orbit both close: the last frame's successor is frame 0's pose.
    Scene a = load(path).scene, b = load(path).scene;
    slow.apply(a, 0.0);
    slow.apply(b, slow.frameCount() / slow.fps());
    for (size_t m = 0; m < a.geometry.meshes.size(); ++m)
        for (size_t i = 0; i < a.geometry.meshes[m].positions.size(); ++i)
            EXPECT_NEAR(glm::length(a.geometry.meshes[m].positions[i] - b.geometry.meshes[m].positions[i]), 0.f, 1e-4f);
}

}  // namespace
}  // namespace rf::anim
