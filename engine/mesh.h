#pragma once
/// Indexed triangle mesh in render space, with optional per-vertex normals, UVs and tangents.
#include <cstdint>
#include <string>
#include <vector>

#include "vec_math.h"

namespace rf {

struct TriangleMesh {
    std::string name;
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;   ///< empty, or one per position (Phong shading)
    std::vector<Vec2> uvs;       ///< empty, or one per position (TEXCOORD_0)
    std::vector<Vec2> uvs1;      ///< empty, or one per position (TEXCOORD_1)
    std::vector<Vec4> tangents;  ///< empty, or one per position (xyz, handedness w)
    std::vector<Vec4> colors;    ///< empty, or one per position (COLOR_0, linear RGBA)
    std::vector<uint32_t> indices;  ///< three per triangle
    int material = 0;

    /// Animated meshes: the node (in Scene::models[model]) that carries the mesh, and the
    /// model-space data re-transformed each frame. node < 0: static, positions are final.
    int model = -1;
    int node = -1;
    std::vector<Vec3> objectPositions;
    std::vector<Vec3> objectNormals;
    std::vector<Vec4> objectTangents;
    /// Morph targets (position deltas per target) and default weights.
    std::vector<std::vector<Vec3>> morphPositions;
    std::vector<std::vector<Vec3>> morphNormals;
    /// Skinned meshes (skin ≥ 0, in Scene::models[model].skins): `influences` joint/weight
    /// pairs per vertex (4 per JOINTS_n/WEIGHTS_n set), joints indexing the skin's joint list
    /// and weights summing to 1. The node's own transform is then not used (glTF 2.0 §3.7.3.3).
    int skin = -1;
    int influences = 0;
    std::vector<uint16_t> skinJoints;
    std::vector<float> skinWeights;

    size_t triangleCount() const { return indices.size() / 3; }
};

}  // namespace rf
