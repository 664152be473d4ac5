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
    /// POINTS, LINES, LINE_LOOP and LINE_STRIP (modes 0–3): mesh has the vertices and no
    /// triangles; wirePoints lists the vertices drawn as dots (every point, or every end of a
    /// line, where its segments join) and wireSegments the lines' segments as index pairs.
    /// wireGeometry() turns them into triangles once their size is known.
    bool wire = false;
    std::vector<uint32_t> wirePoints;
    std::vector<uint32_t> wireSegments;
};

/// Builds primitive `prim` of mesh `meshIndex` (points and lines as PrimitiveGeometry::wire).
/// Returns false when the primitive has nothing to draw. Throws InputError naming the element
/// on inconsistent data. tangents: generate them for a normal-mapped primitive that has none
/// (false when its material is not drawn).
bool buildPrimitive(const tinygltf::Model& model, int meshIndex, int prim, const std::string& file, PrimitiveGeometry& out,
                    bool tangents = true);

/// Points and lines drawn as a ray tracer can: each of g's wirePoints a small sphere of the
/// given radius (an octahedron with the sphere's normals, which at a pixel or two reads as
/// one) and each segment a tube of that radius (six sides, the cylinder's normals) joined at
/// the points into capsules; in g's own (node-local) space. Every new vertex takes the
/// attributes of the vertex it grew from (colour, texture coordinates, joints and weights,
/// morph offsets), so the dots and lines are coloured, skinned and morphed with it. A copy of
/// g with those triangles in mesh (and wire false).
PrimitiveGeometry wireGeometry(const PrimitiveGeometry& g, float radius);

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
