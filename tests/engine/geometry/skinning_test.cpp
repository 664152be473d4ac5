// glTF skinning (engine/geometry/skinning.*, the loader's JOINTS_n/WEIGHTS_n and skins): a two-joint
// strip with one joint turned 90°, positions worked out by hand from the joint matrices;
// normals through a shearing joint; quantized weights against floats; morph before skin.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/geometry/skinning.h"

using namespace rf;
using namespace gltftest;

namespace {

/// How the strip's weights are stored.
enum class WeightType { Float, U8, U16 };

/// A 2×3 strip of vertices (x ∈ {0, 1}, y ∈ {0, 1, 2}) skinned to two joints: node 1 at the
/// origin and its child node 2 at (0, 1, 0), turned 90° about z. Row y = 0 follows joint 0,
/// row 1 is 0.2 / 0.8, row 2 follows joint 1. The mesh node 0 has a translation (5, 0, 0) that
/// skinning must ignore. Inverse bind matrices: identity and translate(0, −1, 0).
struct StripOptions {
    WeightType weights = WeightType::Float;
    bool u16Joints = false;
    bool inverseBind = true;
    int outOfRangeJoint = -1;  ///< ≥ 0: vertex 5's first joint becomes this index
    float weightScale = 1.f;   ///< float weights multiplied by this (sum ≠ 1)
    bool secondSet = false;    ///< move joint 1's share into JOINTS_1/WEIGHTS_1
};

json stripGltf(const StripOptions& o) {
    std::string pos, idx, joints, weights, ibm, joints1, weights1;
    const float rowW0[3] = {1.f, 0.2f, 0.f}, rowW1[3] = {0.f, 0.8f, 1.f};
    const uint8_t rowU8[3] = {0, 204, 255};
    const uint16_t rowU16[3] = {0, 52428, 65535};
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 2; ++x) {
            put<float>(pos, {float(x), float(y), 0.f});
            const int v = 2 * y + x;
            uint16_t j0 = 0, j1 = 1;
            if (v == 5 && o.outOfRangeJoint >= 0) j0 = uint16_t(o.outOfRangeJoint);
            auto putJoints = [&](std::string& buf, uint16_t a, uint16_t b) {
                if (o.u16Joints) put<uint16_t>(buf, {a, b, 0, 0});
                else put<uint8_t>(buf, {uint8_t(a), uint8_t(b), 0, 0});
            };
            auto putWeights = [&](std::string& buf, int row, bool first, bool second) {
                switch (o.weights) {
                    case WeightType::Float: {
                        put<float>(buf, {first ? rowW0[row] * o.weightScale : 0.f, second ? rowW1[row] * o.weightScale : 0.f, 0.f, 0.f});
                        break;
                    }
                    case WeightType::U8: put<uint8_t>(buf, {uint8_t(first ? 255 - rowU8[row] : 0), uint8_t(second ? rowU8[row] : 0), 0, 0}); break;
                    case WeightType::U16: put<uint16_t>(buf, {uint16_t(first ? 65535 - rowU16[row] : 0), uint16_t(second ? rowU16[row] : 0), 0, 0}); break;
                }
            };
            putJoints(joints, j0, j1);
            putWeights(weights, y, true, !o.secondSet);
            if (o.secondSet) {
                putJoints(joints1, j1, 0);
                // joint 1's share in the first component of set 1
                switch (o.weights) {
                    case WeightType::Float: put<float>(weights1, {rowW1[y] * o.weightScale, 0.f, 0.f, 0.f}); break;
                    case WeightType::U8: put<uint8_t>(weights1, {rowU8[y], 0, 0, 0}); break;
                    case WeightType::U16: put<uint16_t>(weights1, {rowU16[y], 0, 0, 0}); break;
                }
            }
        }
    for (int y = 0; y < 2; ++y) {
        const uint16_t a = uint16_t(2 * y), b = uint16_t(a + 1), c = uint16_t(a + 2), d = uint16_t(a + 3);
        put<uint16_t>(idx, {a, b, d, a, d, c});
    }
    put<float>(ibm, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    put<float>(ibm, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1});
    const int wType = o.weights == WeightType::Float ? 5126 : o.weights == WeightType::U8 ? 5121 : 5123;
    const int jType = o.u16Joints ? 5123 : 5121;
    json accessors = json::array(), views = json::array(), buffers = json::array();
    auto add = [&](const std::string& bytes, int type, const std::string& shape, int count, bool normalized) {
        buffers.push_back({{"uri", dataUri(bytes)}, {"byteLength", bytes.size()}});
        views.push_back({{"buffer", buffers.size() - 1}, {"byteLength", bytes.size()}});
        json a = {{"bufferView", views.size() - 1}, {"componentType", type}, {"count", count}, {"type", shape}};
        if (normalized) a["normalized"] = true;
        accessors.push_back(a);
        return int(accessors.size() - 1);
    };
    const int aPos = add(pos, 5126, "VEC3", 6, false);
    accessors[size_t(aPos)]["min"] = {0, 0, 0};
    accessors[size_t(aPos)]["max"] = {1, 2, 0};
    const int aIdx = add(idx, 5123, "SCALAR", 12, false);
    const int aJ = add(joints, jType, "VEC4", 6, false);
    const int aW = add(weights, wType, "VEC4", 6, o.weights != WeightType::Float);
    const int aIbm = add(ibm, 5126, "MAT4", 2, false);
    json attributes = {{"POSITION", aPos}, {"JOINTS_0", aJ}, {"WEIGHTS_0", aW}};
    if (o.secondSet) {
        attributes["JOINTS_1"] = add(joints1, jType, "VEC4", 6, false);
        attributes["WEIGHTS_1"] = add(weights1, wType, "VEC4", 6, o.weights != WeightType::Float);
    }
    json skin = {{"joints", {1, 2}}};
    if (o.inverseBind) skin["inverseBindMatrices"] = aIbm;
    const double s = std::sqrt(0.5);
    return json{{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", {0, 1}}}}},
                {"nodes",
                 {{{"mesh", 0}, {"skin", 0}, {"translation", {5, 0, 0}}},
                  {{"children", {2}}},
                  {{"translation", {0, 1, 0}}, {"rotation", {0, 0, s, s}}}}},
                {"meshes", {{{"primitives", {{{"attributes", attributes}, {"indices", aIdx}}}}}}},
                {"skins", {skin}},
                {"accessors", accessors},
                {"bufferViews", views},
                {"buffers", buffers}};
}

Scene loadStrip(const StripOptions& o, const TempDir& dir) {
    const std::string path = dir / "strip.gltf";
    writeFile(path, stripGltf(o).dump());
    DiskFileSource fs;
    return loadGltfScene(path, fs);
}

/// World positions of the strip's six vertices, in file order.
std::vector<glm::dvec3> worldPositions(const Scene& s) {
    EXPECT_EQ(s.geometry.meshes.size(), 1u);
    std::vector<glm::dvec3> out;
    for (const Vec3& p : s.geometry.meshes[0].positions) out.push_back(glm::dvec3(p) + s.renderOrigin);
    return out;
}

TEST(Skinning, TwoJointStripLandsWhereTheJointMatricesPutIt) {
    TempDir dir;
    const Scene s = loadStrip({}, dir);
    const std::vector<glm::dvec3> p = worldPositions(s);
    ASSERT_EQ(p.size(), 6u);
    // Joint 0 = identity; joint 1 = translate(0,1,0)·Rz(90°)·translate(0,−1,0): (x, y) → (1 − y, x + 1).
    // Row 0: (x, 0). Row 1: 0.2·(x, 1) + 0.8·(0, 1 + x) = (0.2x, 1 + 0.8x). Row 2: (−1, 1 + x).
    // The mesh node's translation (5, 0, 0) is not applied.
    const glm::dvec3 expected[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 1.8, 0}, {-1, 1, 0}, {-1, 2, 0}};
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(p[size_t(i)][c], expected[i][c], 1e-6) << "vertex " << i << " axis " << c;
    ASSERT_EQ(s.geometry.models.size(), 1u);
    ASSERT_EQ(s.geometry.models[0].skins.size(), 1u);
    EXPECT_EQ(s.geometry.models[0].skins[0].joints, (std::vector<int>{1, 2}));
    for (const std::string& n : s.notes) EXPECT_EQ(n.find("skins are not supported"), std::string::npos) << n;
}

TEST(Skinning, AbsentInverseBindMatricesAreTheIdentity) {
    TempDir dir;
    StripOptions o;
    o.inverseBind = false;
    const std::vector<glm::dvec3> p = worldPositions(loadStrip(o, dir));
    // Joint 1 = translate(0,1,0)·Rz(90°): (x, y) → (−y, x + 1). Row 2 vertex x=1: (−2, 2).
    EXPECT_NEAR(p[5].x, -2.0, 1e-6);
    EXPECT_NEAR(p[5].y, 2.0, 1e-6);
    EXPECT_NEAR(p[0].x, 0.0, 1e-6);  // joint 0 still the identity
}

TEST(Skinning, NormalizedU8AndU16WeightsSkinExactlyLikeFloats) {
    TempDir dir;
    const std::vector<Vec3> ref = loadStrip({}, dir).geometry.meshes[0].positions;
    for (WeightType t : {WeightType::U8, WeightType::U16})
        for (bool u16Joints : {false, true}) {
            StripOptions o;
            o.weights = t;
            o.u16Joints = u16Joints;
            const Scene s = loadStrip(o, dir);
            EXPECT_EQ(s.geometry.meshes[0].positions, ref) << "weights " << int(t) << " u16 joints " << u16Joints;
        }
}

TEST(Skinning, EverySetOfJointsAndWeightsCounts) {
    TempDir dir;
    StripOptions o;
    o.secondSet = true;
    const Scene s = loadStrip(o, dir);
    EXPECT_EQ(s.geometry.meshes[0].influences, 8);
    const std::vector<Vec3> ref = loadStrip({}, dir).geometry.meshes[0].positions;
    EXPECT_EQ(s.geometry.meshes[0].positions, ref);
}

TEST(Skinning, WeightsThatDoNotSumToOneAreNormalizedWithOneNote) {
    TempDir dir;
    StripOptions o;
    o.weightScale = 2.f;
    const Scene s = loadStrip(o, dir);
    const std::vector<glm::dvec3> p = worldPositions(s);
    EXPECT_NEAR(p[3].x, 0.2, 1e-6);  // as with weights summing to 1 (doubled they would give 0.4)
    EXPECT_NEAR(p[3].y, 1.8, 1e-6);
    int notes = 0;
    for (const std::string& n : s.notes) notes += n.find("do not sum to 1; normalized") != std::string::npos;
    EXPECT_EQ(notes, 1);
    const Scene ok = loadStrip({}, dir);
    for (const std::string& n : ok.notes) EXPECT_EQ(n.find("sum to 1"), std::string::npos) << n;
}

TEST(Skinning, AJointIndexOutOfRangeIsRefusedNamingTheAccessor) {
    TempDir dir;
    StripOptions o;
    o.outOfRangeJoint = 7;
    try {
        loadStrip(o, dir);
        FAIL() << "joint 7 of a two-joint skin accepted";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("JOINTS_0 (accessors[2])"), std::string::npos) << m;
        EXPECT_NE(m.find("joint 7"), std::string::npos) << m;
        EXPECT_NE(m.find("2 joints"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

/// A one-triangle skinned mesh for poseMesh alone.
TriangleMesh skinnedTriangle() {
    TriangleMesh m;
    m.objectPositions = {{0, 0, 0}, {1, 0, 1}, {0, 1, 0}};
    const Vec3 n = glm::normalize(glm::cross(m.objectPositions[1] - m.objectPositions[0], m.objectPositions[2] - m.objectPositions[0]));
    m.objectNormals = {n, n, n};
    m.objectTangents = {Vec4(glm::normalize(m.objectPositions[1]), -1.f), Vec4(glm::normalize(m.objectPositions[1]), -1.f),
                        Vec4(glm::normalize(m.objectPositions[1]), -1.f)};
    m.positions = m.objectPositions;
    m.normals = m.objectNormals;
    m.tangents = m.objectTangents;
    m.indices = {0, 1, 2};
    m.skin = 0;
    m.influences = 4;
    m.skinJoints.assign(12, 0);
    m.skinWeights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    return m;
}

TEST(Skinning, NormalsStayUnitAndPerpendicularThroughAShearingJoint) {
    TriangleMesh m = skinnedTriangle();
    // Non-uniform scale after a rotation: a shear, where the plain matrix would tilt the normal.
    const DMat4 j = glm::translate(DMat4(1.0), glm::dvec3(2, -1, 3)) * glm::scale(DMat4(1.0), glm::dvec3(3, 1, 0.5)) *
                    glm::rotate(DMat4(1.0), glm::radians(30.0), glm::dvec3(0, 0, 1));
    const std::vector<DMat4> joints = {j};
    poseMesh(m, DMat4(1.0), &joints, nullptr);
    const glm::dvec3 e1 = glm::dvec3(m.positions[1] - m.positions[0]), e2 = glm::dvec3(m.positions[2] - m.positions[0]);
    for (int i = 0; i < 3; ++i) {
        const glm::dvec3 n(m.normals[size_t(i)]);
        EXPECT_NEAR(glm::length(n), 1.0, 1e-6);
        EXPECT_NEAR(glm::dot(n, e1) / glm::length(e1), 0.0, 1e-6);
        EXPECT_NEAR(glm::dot(n, e2) / glm::length(e2), 0.0, 1e-6);
        EXPECT_GT(glm::dot(n, glm::cross(e1, e2)), 0.0);  // the same side as the winding
        // Tangents follow the surface, unit length, w kept.
        const glm::dvec3 t(Vec3(m.tangents[size_t(i)]));
        EXPECT_NEAR(glm::length(t), 1.0, 1e-6);
        EXPECT_NEAR(glm::dot(t, glm::normalize(e1)), 1.0, 1e-6);
        EXPECT_EQ(m.tangents[size_t(i)].w, -1.f);
    }
    // The test can fail: the matrix itself would not keep the normal perpendicular.
    const glm::dvec3 naive = glm::normalize(glm::dmat3(j) * glm::dvec3(m.objectNormals[0]));
    EXPECT_GT(std::abs(glm::dot(naive, e1) / glm::length(e1)), 1e-2);
}

TEST(Skinning, BlendedVerticesUseTheWeightedSumOfJointMatrices) {
    TriangleMesh m = skinnedTriangle();
    m.skinJoints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
    m.skinWeights = {0.25f, 0.75f, 0, 0, 0.25f, 0.75f, 0, 0, 0.25f, 0.75f, 0, 0};
    const DMat4 a = glm::translate(DMat4(1.0), glm::dvec3(4, 0, 0));
    const DMat4 b = glm::rotate(DMat4(1.0), glm::radians(90.0), glm::dvec3(1, 0, 0));
    const std::vector<DMat4> joints = {a, b};
    poseMesh(m, DMat4(1.0), &joints, nullptr);
    // Vertex 1 (1, 0, 1): 0.25·(5, 0, 1) + 0.75·(1, −1, 0) = (2, −0.75, 0.25).
    EXPECT_NEAR(m.positions[1].x, 2.0, 1e-6);
    EXPECT_NEAR(m.positions[1].y, -0.75, 1e-6);
    EXPECT_NEAR(m.positions[1].z, 0.25, 1e-6);
}

TEST(Skinning, MorphTargetsApplyBeforeTheSkin) {
    TriangleMesh m = skinnedTriangle();
    m.morphPositions = {{{0, 0, 1}, {0, 0, 0}, {0, 0, 0}}};
    // Rotation 90° about x: (x, y, z) → (x, −z, y). Morph first: (0, 0, 0.5) → (0, −0.5, 0);
    // skin first then morph would give (0, 0, 0.5).
    const std::vector<DMat4> joints = {glm::rotate(DMat4(1.0), glm::radians(90.0), glm::dvec3(1, 0, 0))};
    const std::vector<double> w = {0.5};
    poseMesh(m, DMat4(1.0), &joints, &w);
    EXPECT_NEAR(m.positions[0].x, 0.0, 1e-6);
    EXPECT_NEAR(m.positions[0].y, -0.5, 1e-6);
    EXPECT_NEAR(m.positions[0].z, 0.0, 1e-6);
}

TEST(Skinning, JointMatricesComposeTheJointTransformWithItsInverseBind) {
    Skin skin;
    skin.joints = {1, 0};
    skin.inverseBind = {glm::translate(DMat4(1.0), glm::dvec3(0, -1, 0)), DMat4(1.0)};
    const std::vector<DMat4> nodes = {glm::scale(DMat4(1.0), glm::dvec3(2.0)), glm::translate(DMat4(1.0), glm::dvec3(0, 1, 0))};
    const std::vector<DMat4> j = jointMatrices(skin, nodes);
    ASSERT_EQ(j.size(), 2u);
    EXPECT_EQ(j[0], DMat4(1.0));  // translate(0,1,0)·translate(0,−1,0)
    EXPECT_EQ(j[1], nodes[0]);
}

}  // namespace

namespace {

/// 256 small triangles along x, one mesh, BVH built.
Scene rowOfTriangles() {
    Scene s;
    TriangleMesh m;
    for (int i = 0; i < 256; ++i) {
        const float x = 0.1f * float(i);
        const uint32_t b = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {{x, 0.f, 0.f}, {x + 0.05f, 0.f, 0.f}, {x, 0.05f, 0.f}});
        m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
    }
    s.geometry.meshes.push_back(m);
    s.materials.emplace_back();
    s.build();
    return s;
}

/// Pose: the row folded `fold` of the way over (0: the built pose, moved by `nudge` in z; 1:
/// every odd triangle mirrored to the far end, so neighbours in the built tree lie apart).
float foldedX(int tri, float fold) {
    const float x = 0.1f * float(tri);
    return tri % 2 ? x + fold * (25.5f - 2.f * x) : x;
}
void pose(Scene& s, float fold, float nudge = 0.f) {
    TriangleMesh& m = s.geometry.meshes[0];
    for (size_t v = 0; v < m.positions.size(); ++v) {
        const int tri = int(v / 3), k = int(v % 3);
        const float y = (k == 2 ? 0.05f : 0.f) + (tri % 2 ? 1.f : 0.f) * fold;
        m.positions[v] = Vec3(foldedX(tri, fold) + (k == 1 ? 0.05f : 0.f), y, nudge);
    }
    s.geometry.refit();
}

TEST(MovingMeshBvh, RefitsWhileGoodRebuildsWhenTheSahCostGrows) {
    Scene s = rowOfTriangles();
    ASSERT_TRUE(s.geometry.usesBvh());
    pose(s, 0.f, 0.01f);  // a small move: the refitted tree is as good as a new one
    EXPECT_FALSE(s.geometry.lastRefitRebuilt());
    pose(s, 1.f);  // folded: every refitted node spans the whole row
    EXPECT_TRUE(s.geometry.lastRefitRebuilt());
    // Still correct: a ray down onto each triangle hits that one.
    for (int tri : {0, 1, 100, 255}) {
        const float y = (tri % 2 ? 1.f : 0.f) + 0.01f;
        Ray r;
        r.o = Vec3(foldedX(tri, 1.f) + 0.01f, y, 1.f);
        r.d = Vec3(0.f, 0.f, -1.f);
        r.tMax = 10.f;
        Hit h;
        ASSERT_TRUE(s.geometry.intersect(r, h)) << tri;
        EXPECT_NEAR(h.t, 1.0, 1e-5) << tri;
    }
}

TEST(MovingMeshBvh, TheTreeIsAFunctionOfThePoseAlone) {
    // Pose B reached directly, or after another spread pose, or after a small one: one tree.
    Scene direct = rowOfTriangles(), viaSpread = rowOfTriangles(), viaSmall = rowOfTriangles();
    pose(direct, 0.9f);
    ASSERT_TRUE(direct.geometry.lastRefitRebuilt());
    pose(viaSpread, 1.f);
    pose(viaSpread, 0.9f);
    pose(viaSmall, 0.f, 0.3f);
    pose(viaSmall, 0.9f);
    for (const Scene* s : {&viaSpread, &viaSmall}) {
        EXPECT_EQ(s->geometry.bvh().primIndex(), direct.geometry.bvh().primIndex());
        ASSERT_EQ(s->geometry.bvh().nodes().size(), direct.geometry.bvh().nodes().size());
        for (size_t i = 0; i < direct.geometry.bvh().nodes().size(); ++i) {
            EXPECT_EQ(s->geometry.bvh().nodes()[i].box.lo, direct.geometry.bvh().nodes()[i].box.lo);
            EXPECT_EQ(s->geometry.bvh().nodes()[i].box.hi, direct.geometry.bvh().nodes()[i].box.hi);
        }
    }
    // And back at a small pose the built tree's topology is used again.
    Scene fresh = rowOfTriangles();
    pose(fresh, 0.f, 0.2f);
    pose(direct, 0.f, 0.2f);
    EXPECT_FALSE(direct.geometry.lastRefitRebuilt());
    EXPECT_EQ(direct.geometry.bvh().primIndex(), fresh.geometry.bvh().primIndex());
}

}  // namespace
