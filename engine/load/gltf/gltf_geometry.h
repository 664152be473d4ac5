#pragma once
/// One glTF mesh primitive as engine triangles in the mesh's own (node-local) space: strips and
/// fans unrolled, degenerate and non-finite triangles dropped and counted, missing normals
/// generated, morph targets read.
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/geometry/mesh.h"

namespace rf::gltf {

struct PrimitiveGeometry {
    TriangleMesh mesh;           ///< positions without morph offsets; normals always present
    bool generatedNormals = false;
    size_t droppedDegenerate = 0;
    size_t droppedNonFinite = 0;
    size_t outsideBounds = 0;     ///< vertices outside POSITION's declared min/max (their triangles dropped)
    bool boundsMissing = false;   ///< POSITION has no min/max, which glTF requires
    size_t leftoverIndices = 0;   ///< TRIANGLES indices past the last multiple of 3
    int gltfMaterial = -1;        ///< -1 also when the file's index is out of range
    bool materialOutOfRange = false;
    /// JOINTS_n/WEIGHTS_n (mesh.influences, skinJoints, skinWeights): per set its JOINTS
    /// accessor and the largest joint index in it (with a vertex that has it), for the node
    /// that binds a skin to check against its joint count.
    struct JointSet {
        int accessor = -1;
        int set = 0;
        uint32_t maxJoint = 0;
        size_t vertex = 0;
    };
    std::vector<JointSet> jointSets;
    size_t weightsNormalized = 0;  ///< vertices whose weights did not sum to 1 (now normalized)
    size_t weightsZero = 0;        ///< vertices with no weight at all (bound to their first joint)
};

/// Builds primitive `prim` of mesh `meshIndex`. Returns false (and builds nothing) for points
/// and lines. Throws InputError naming the element on inconsistent data. tangents: generate
/// them for a normal-mapped primitive that has none (false when its material is not drawn).
bool buildPrimitive(const tinygltf::Model& model, int meshIndex, int prim, const std::string& file, PrimitiveGeometry& out,
                    bool tangents = true);

/// Positions with the morph targets applied at `weights` (missing weights count as 0).
std::vector<Vec3> morphedPositions(const TriangleMesh& mesh, const std::vector<double>& weights);
/// Tangents with the morph targets' TANGENT deltas applied at `weights` (w kept, not renormalized).
std::vector<Vec4> morphedTangents(const TriangleMesh& mesh, const std::vector<double>& weights);
/// Normals with the morph targets applied at `weights` (not renormalized).
std::vector<Vec3> morphedNormals(const TriangleMesh& mesh, const std::vector<double>& weights);

/// Area-weighted vertex normals from the triangles (zero where no triangle touches a vertex).
std::vector<Vec3> generateNormals(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices);

/// Moves a primitive's triangles into render space by renderFromNode (morph weights applied,
/// normals by the inverse transpose, winding flipped under a mirroring transform, or, with
/// flipWinding false (a moving mesh, whose indices must keep the file's order), mesh.mirrored
/// set instead). Returns false if nothing drawable is left (zero or non-finite scale).
bool placePrimitive(TriangleMesh& mesh, const DMat4& renderFromNode, const std::vector<double>& weights, bool flipWinding = true);

/// Per-vertex tangents (xyz, handedness w) from UV gradients, orthogonal to the normals; zero
/// where the UVs give no direction.
std::vector<Vec4> generateTangents(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                   const std::vector<Vec2>& uvs, const std::vector<uint32_t>& indices);

}  // namespace rf::gltf
