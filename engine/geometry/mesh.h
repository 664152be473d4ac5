#pragma once
/// Indexed triangle mesh in render space, with optional per-vertex normals, UVs and tangents.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/util/vec_math.h"

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

    /// Animated meshes: the node (in SceneGeometry::models[model]) that carries the mesh, and the
    /// model-space data re-transformed each frame. node < 0: static, positions are final.
    int model = -1;
    int node = -1;
    std::vector<Vec3> objectPositions;
    std::vector<Vec3> objectNormals;
    std::vector<Vec4> objectTangents;
    /// A rigid moving mesh (node ≥ 0, no skin, no morph targets): the node's matrix that took
    /// object space to render space for the current positions. The scene's acceleration
    /// structure keeps the mesh's own tree in object space and moves it by this matrix.
    DMat4 renderFromObject{1.0};
    /// Morph targets: position, normal and tangent (xyz) deltas per target, each empty or one
    /// per vertex.
    std::vector<std::vector<Vec3>> morphPositions;
    std::vector<std::vector<Vec3>> morphNormals;
    std::vector<std::vector<Vec3>> morphTangents;
    /// A moving mesh whose pose mirrors (a matrix of negative determinant) turns the file's
    /// counter-clockwise front faces clockwise; the indices keep the file's order and
    /// SceneGeometry::interaction turns the facet normal round instead: the whole mesh (rigid), or per
    /// vertex (skinned: its skin matrix; empty when no vertex is mirrored), by majority.
    bool mirrored = false;
    std::vector<uint8_t> mirroredVertices;
    /// Skinned meshes (skin ≥ 0, in SceneGeometry::models[model].skins): `influences` joint/weight
    /// pairs per vertex (4 per JOINTS_n/WEIGHTS_n set), joints indexing the skin's joint list
    /// and weights summing to 1. The node's own transform is then not used (glTF 2.0 §3.7.3.3).
    int skin = -1;
    int influences = 0;
    std::vector<uint16_t> skinJoints;
    std::vector<float> skinWeights;

    size_t triangleCount() const { return indices.size() / 3; }
};

}  // namespace rf
