// assimp's bones as glTF skin data (engine/load/assimp/assimp_skin.h), on meshes made here with
// every case a file can hold (more than 8 weights, none, weights that do not sum to 1, weights
// of no vertex), and on Blender's skinned FBX and COLLADA as the glTF model they become.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <assimp/mesh.h>

#include "engine/util/file_source.h"
#include "engine/load/assimp/assimp_import.h"
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
