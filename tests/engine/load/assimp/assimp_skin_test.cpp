// assimp's bones and morph targets as glTF skin and morph data (engine/load/assimp/assimp_skin.h,
// assimp_morph.h), on meshes made here with every case a file can hold (more than 8 weights,
// none, weights that do not sum to 1, sparse morph keys, targets without normals), and on
// Blender's skinned FBX and COLLADA and shape-keyed FBX as the glTF model they become.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <assimp/anim.h>
#include <assimp/mesh.h>

#include "engine/util/file_source.h"
#include "engine/load/assimp/assimp_import.h"
#include "engine/load/assimp/assimp_morph.h"
#include "engine/load/assimp/assimp_skin.h"

using namespace rf;

namespace {

/// A mesh of `vertices` vertices and `bones` bones (named b0, b1, …), each bone's weights as given.
void makeMesh(aiMesh& m, unsigned vertices, const std::vector<std::vector<aiVertexWeight>>& bones) {
    m.mNumVertices = vertices;
    m.mVertices = new aiVector3D[vertices];
    m.mNumBones = unsigned(bones.size());
    m.mBones = new aiBone*[bones.size()];
    for (size_t b = 0; b < bones.size(); ++b) {
        auto* bone = new aiBone;
        std::string name = std::to_string(b);
        name.insert(name.begin(), 'b');  // not "b" + …: GCC 12 warns of a restrict overlap there
        bone->mName = aiString(name);
        bone->mNumWeights = unsigned(bones[b].size());
        bone->mWeights = new aiVertexWeight[bones[b].size()];
        for (size_t k = 0; k < bones[b].size(); ++k) bone->mWeights[k] = bones[b][k];
        m.mBones[b] = bone;
    }
}

}  // namespace

TEST(AssimpSkin, LargestEightWeightsDividedByTheirSumAndUnweightedVerticesFollowTheMeshNode) {
    // Vertex 0: ten bones weigh it 1…10. Vertex 1: two bones, 0.2 each. Vertex 2: none.
    // Vertex 3: only a negative weight. And a weight of vertex 99, which the mesh lacks.
    std::vector<std::vector<aiVertexWeight>> bones(10);
    for (unsigned b = 0; b < 10; ++b) bones[b].emplace_back(0, float(b + 1));
    bones[3].emplace_back(1, 0.2f);
    bones[4].emplace_back(1, 0.2f);
    bones[5].emplace_back(3, -0.5f);
    bones[6].emplace_back(99, 1.f);
    aiMesh m;
    makeMesh(m, 4, bones);
    m.mBones[2]->mOffsetMatrix = aiMatrix4x4(aiVector3D(1.f), aiQuaternion(), aiVector3D(1.f, 2.f, 3.f));
    const AssimpSkin s = assimpSkin(m);
    ASSERT_TRUE(s.refused.empty()) << s.refused;
    ASSERT_EQ(s.sets, 2);  // 8 influences kept of vertex 0's ten
    ASSERT_EQ(s.jointNames.size(), 11u);  // the ten bones, then the mesh's own node
    EXPECT_EQ(s.jointNames[2], "b2");
    EXPECT_EQ(s.jointNames[10], "");
    // Offset matrices column-major: bone 2's translation in the last column.
    EXPECT_EQ(s.inverseBind[2 * 16 + 12], 1.f);
    EXPECT_EQ(s.inverseBind[2 * 16 + 13], 2.f);
    EXPECT_EQ(s.inverseBind[2 * 16 + 14], 3.f);
    EXPECT_EQ(s.inverseBind[10 * 16 + 0], 1.f);  // the mesh node's: the identity
    EXPECT_EQ(s.inverseBind[10 * 16 + 12], 0.f);
    EXPECT_EQ(s.verticesOverCap, 1u);
    EXPECT_EQ(s.unweighted, 2u);
    EXPECT_EQ(s.weightsDropped, 2u);

    // Vertex 0 keeps bones 9 down to 2 (weights 10…3, 52 in all), each divided by 52.
    double sum = 0.0;
    for (int k = 0; k < 8; ++k) {
        EXPECT_EQ(s.joints[size_t(k)], uint16_t(9 - k));
        EXPECT_NEAR(s.weights[size_t(k)], (10.0 - k) / 52.0, 1e-6);
        sum += s.weights[size_t(k)];
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    // Vertex 1: 0.5 and 0.5; the rest of its 8 slots empty.
    EXPECT_EQ(s.joints[8], 3);
    EXPECT_EQ(s.joints[9], 4);
    EXPECT_NEAR(s.weights[8], 0.5, 1e-6);
    EXPECT_NEAR(s.weights[9], 0.5, 1e-6);
    for (int k = 2; k < 8; ++k) EXPECT_EQ(s.weights[size_t(8 + k)], 0.f);
    // Vertices 2 and 3 follow joint 10, the mesh's node, alone.
    for (size_t v : {2u, 3u}) {
        EXPECT_EQ(s.joints[v * 8], 10) << v;
        EXPECT_EQ(s.weights[v * 8], 1.f) << v;
        for (size_t k = 1; k < 8; ++k) EXPECT_EQ(s.weights[v * 8 + k], 0.f) << v;
    }
}

TEST(AssimpSkin, FourWeightsOrFewerMakeOneSetAndNoExtraJoint) {
    aiMesh m;
    makeMesh(m, 2, {{{0, 0.25f}, {1, 1.f}}, {{0, 0.75f}}});
    const AssimpSkin s = assimpSkin(m);
    EXPECT_EQ(s.sets, 1);
    EXPECT_EQ(s.jointNames.size(), 2u);
    EXPECT_EQ(s.unweighted + s.verticesOverCap + s.weightsDropped, 0u);
    EXPECT_NEAR(s.weights[0], 0.25, 1e-6);
    EXPECT_NEAR(s.weights[1], 0.75, 1e-6);
    EXPECT_EQ(s.joints[4], 0);
    EXPECT_NEAR(s.weights[4], 1.0, 1e-6);
}

TEST(AssimpSkin, NonFiniteOffsetMatrixIsRefusedAndMeshesWithoutBonesAreNotSkins) {
    aiMesh plain;
    plain.mNumVertices = 1;
    plain.mVertices = new aiVector3D[1];
    EXPECT_EQ(assimpSkin(plain).sets, 0);
    aiMesh m;
    makeMesh(m, 1, {{{0, 1.f}}});
    m.mBones[0]->mOffsetMatrix.b2 = std::nanf("");
    const AssimpSkin s = assimpSkin(m);
    EXPECT_EQ(s.sets, 0);
    EXPECT_NE(s.refused.find("non-finite offset matrix"), std::string::npos) << s.refused;
}

// Blender's skinned tube as the glTF model it becomes: one skin of the armature's three bones
// on a node of its own, JOINTS_0/WEIGHTS_0 on its primitive, the bones' nodes its joints.
TEST(AssimpSkin, BlenderFbxAndColladaSkinsBecomeGltfSkins) {
    for (const char* name : {"skinned.fbx", "skinned.dae"}) {
        DiskFileSource files;
        std::vector<std::string> notes;
        const tinygltf::Model g =
            importAssimpModel(std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/assimp/" + name, files, {}, notes);
        ASSERT_EQ(g.skins.size(), 1u) << name;
        const tinygltf::Skin& skin = g.skins[0];
        ASSERT_EQ(skin.joints.size(), 3u) << name;
        // Blender's COLLADA exporter names a bone's node after its armature too ("rig_root").
        const std::string prefix = std::string(name) == "skinned.dae" ? "rig_" : "";
        std::vector<std::string> joints;
        for (int j : skin.joints) joints.push_back(g.nodes[size_t(j)].name);
        EXPECT_EQ(joints, (std::vector<std::string>{prefix + "root", prefix + "middle", prefix + "top"})) << name;
        ASSERT_GE(skin.inverseBindMatrices, 0);
        EXPECT_EQ(g.accessors[size_t(skin.inverseBindMatrices)].count, 3u);
        int skinned = 0;
        for (const tinygltf::Node& n : g.nodes) {
            if (n.skin != 0) continue;
            ++skinned;
            ASSERT_GE(n.mesh, 0);
            const tinygltf::Primitive& p = g.meshes[size_t(n.mesh)].primitives.at(0);
            EXPECT_TRUE(p.attributes.count("JOINTS_0") && p.attributes.count("WEIGHTS_0")) << name;
            EXPECT_FALSE(p.attributes.count("JOINTS_1")) << name << ": at most 2 weights a vertex in the file";
        }
        EXPECT_EQ(skinned, 1) << name;
        for (const std::string& n : notes) EXPECT_EQ(n.find("bind pose"), std::string::npos) << name << ": " << n;
    }
}

// Blender's FBX shape keys as glTF morph targets: two targets on the sphere's own node, its
// weights 0 at rest, one "weights" channel; Blender writes each shape's normals as the base's,
// so their offsets are made from the positions (the top of "tall" keeps pointing up, the side
// of "wide" turns towards ±X less: non-zero offsets, as the GLB's own targets have).
TEST(AssimpMorph, BlenderFbxShapeKeysBecomeGltfMorphTargets) {
    DiskFileSource files;
    std::vector<std::string> notes;
    const tinygltf::Model g = importAssimpModel(std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/assimp/morph.fbx", files, {}, notes);
    int morphed = -1;
    for (size_t i = 0; i < g.nodes.size(); ++i)
        if (g.nodes[i].mesh >= 0 && !g.meshes[size_t(g.nodes[i].mesh)].primitives.at(0).targets.empty()) morphed = int(i);
    ASSERT_GE(morphed, 0);
    const tinygltf::Mesh& mesh = g.meshes[size_t(g.nodes[size_t(morphed)].mesh)];
    EXPECT_EQ(mesh.weights, (std::vector<double>{0.0, 0.0}));
    const auto& targets = mesh.primitives.at(0).targets;
    ASSERT_EQ(targets.size(), 2u);
    for (const auto& t : targets) {
        ASSERT_TRUE(t.count("POSITION") && t.count("NORMAL"));
        const tinygltf::Accessor& a = g.accessors[size_t(t.at("NORMAL"))];
        const tinygltf::BufferView& v = g.bufferViews[size_t(a.bufferView)];
        const auto* f = reinterpret_cast<const float*>(g.buffers[0].data.data() + v.byteOffset);
        double largest = 0.0;
        for (size_t k = 0; k < a.count * 3; ++k) largest = std::max(largest, double(std::abs(f[k])));
        EXPECT_GT(largest, 0.2) << "normal offsets of a target that moves the surface";
    }
    ASSERT_EQ(g.animations.size(), 1u);
    ASSERT_EQ(g.animations[0].channels.size(), 1u);
    EXPECT_EQ(g.animations[0].channels[0].target_path, "weights");
    EXPECT_EQ(g.animations[0].channels[0].target_node, morphed);
    const tinygltf::AnimationSampler& s = g.animations[0].samplers[0];
    EXPECT_EQ(g.accessors[size_t(s.output)].count, 2 * g.accessors[size_t(s.input)].count);
}

// A morph channel whose keys name only the targets keyed there (as assimp gives FBX's): each
// target is interpolated between its own keys, held past its ends, 0 when never keyed.
TEST(AssimpMorph, SparseKeysAreInterpolatedPerTarget) {
    aiMeshMorphAnim ch;
    ch.mNumKeys = 3;
    ch.mKeys = new aiMeshMorphKey[3];  // freed by aiMeshMorphAnim, with each key's arrays
    auto key = [&](unsigned k, double time, std::vector<std::pair<unsigned, double>> vw) {
        aiMeshMorphKey& K = ch.mKeys[k];
        K.mTime = time;
        K.mNumValuesAndWeights = unsigned(vw.size());
        K.mValues = new unsigned[vw.size()];
        K.mWeights = new double[vw.size()];
        for (size_t i = 0; i < vw.size(); ++i) K.mValues[i] = vw[i].first, K.mWeights[i] = vw[i].second;
    };
    key(0, 0.0, {{0, 0.0}, {1, 0.2}});
    key(1, 10.0, {{0, 1.0}, {7, 0.5}});  // target 7: beyond the 3 the mesh has
    key(2, 40.0, {{1, 0.8}});
    const MorphTrack t = morphTrack(ch, 3);
    ASSERT_EQ(t.times, (std::vector<double>{0.0, 10.0, 40.0}));
    ASSERT_EQ(t.weights.size(), 9u);
    EXPECT_EQ(t.outOfRange, 1u);
    // target 0: 0, 1, then held at 1; target 1: 0.2, 0.2 + 0.6·10/40 = 0.35, 0.8; target 2: 0.
    const float want[9] = {0.f, 0.2f, 0.f, 1.f, 0.35f, 0.f, 1.f, 0.8f, 0.f};
    for (size_t i = 0; i < 9; ++i) EXPECT_NEAR(t.weights[i], want[i], 1e-6) << i;
}

TEST(AssimpMorph, ChannelNamesNameTheirNode) {
    EXPECT_EQ(morphChannelNode("Sphere*0"), "Sphere");    // FBX: node * geometry index
    EXPECT_EQ(morphChannelNode("Head*12"), "Head");
    EXPECT_EQ(morphChannelNode("face-node"), "face-node");  // COLLADA: the node
    EXPECT_EQ(morphChannelNode("a*b"), "a*b");
    EXPECT_EQ(morphChannelNode("star*"), "star*");
}

// A target that moves the surface, given without normals, gets normal offsets that turn each
// normal as its triangles turn: a flat quad in z = 0 (normals +Z) whose target lifts one edge
// by its width tilts 45° about X.
TEST(AssimpMorph, NormalsOfATargetWithoutThemFollowItsTriangles) {
    aiMesh m;
    m.mNumVertices = 4;
    m.mVertices = new aiVector3D[4]{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.mNormals = new aiVector3D[4]{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.mNumFaces = 2;
    m.mFaces = new aiFace[2];
    for (unsigned f = 0; f < 2; ++f) {
        m.mFaces[f].mNumIndices = 3;
        m.mFaces[f].mIndices = f == 0 ? new unsigned[3]{0, 1, 2} : new unsigned[3]{0, 2, 3};
    }
    m.mNumAnimMeshes = 1;
    m.mAnimMeshes = new aiAnimMesh*[1];
    m.mAnimMeshes[0] = new aiAnimMesh;
    m.mAnimMeshes[0]->mNumVertices = 4;
    m.mAnimMeshes[0]->mVertices = new aiVector3D[4]{{0, 0, 0}, {1, 0, 0}, {1, 1, 1}, {0, 1, 1}};
    const AssimpMorph morph = assimpMorph(m);
    ASSERT_EQ(morph.targets(), 1u);
    EXPECT_EQ(morph.derivedNormals, 1u);
    ASSERT_EQ(morph.normals[0].size(), 4u);
    const float s = std::sqrt(0.5f);
    for (size_t i = 0; i < 4; ++i) {
        const aiVector3D n = m.mNormals[i] + morph.normals[0][i];
        EXPECT_NEAR(n.x, 0.f, 1e-5) << i;
        EXPECT_NEAR(n.y, -s, 1e-5) << i;
        EXPECT_NEAR(n.z, s, 1e-5) << i;
        EXPECT_NEAR(morph.positions[0][i].z, i >= 2 ? 1.f : 0.f, 1e-6) << i;
    }
}
