#pragma once
/// Morph targets of an assimp mesh (FBX blend shapes, COLLADA morph controllers; assimp's
/// aiAnimMesh) as glTF's: a position offset (and normal offset) a vertex per target, and
/// assimp's morph channels (aiMeshMorphAnim) as the per-key weights a glTF "weights" channel
/// holds. assimp_import.cpp writes them into the model.
#include <cstddef>
#include <string>
#include <vector>

#include <assimp/vector3.h>

struct aiMesh;
struct aiMeshMorphAnim;

namespace rf {

struct AssimpMorph {
    /// Per target, per vertex of the mesh: the offset from the base mesh. assimp stores a
    /// target's positions whole (the base plus the shape's offset) but for COLLADA's RELATIVE
    /// method, whose targets are offsets already.
    std::vector<std::vector<aiVector3D>> positions;
    /// Per target, the normals' offsets; empty for a target (or every target) without normals.
    std::vector<std::vector<aiVector3D>> normals;
    std::vector<std::string> names;
    size_t unusable = 0;  ///< targets without positions, or not one a vertex: kept as no offset
    /// Targets whose normals were made from their positions (the file gave none that differ
    /// from the base's): each vertex's normal turned as the surface around it turns.
    size_t derivedNormals = 0;
    size_t targets() const { return positions.size(); }
};

/// The morph targets of m (none when it has no aiAnimMesh). Linear in vertices × targets.
AssimpMorph assimpMorph(const aiMesh& m);

/// A morph channel as glTF weights: the times of all its keys (in assimp's ticks, increasing),
/// and at each, every target's weight (times × targets, row by row). assimp lists at a key
/// only the targets keyed there (FBX: those whose curve has a key at that time); the others
/// are interpolated linearly between their own keys, held before their first and after their
/// last, 0 when never keyed. Targets a key names beyond `targets` are ignored (counted).
struct MorphTrack {
    std::vector<double> times;
    std::vector<float> weights;
    size_t outOfRange = 0;
};
MorphTrack morphTrack(const aiMeshMorphAnim& channel, size_t targets);

/// The node a morph channel animates: assimp names FBX's "NODE*GEOMETRY" (the geometry's
/// index in the node) and COLLADA's by the node alone.
std::string morphChannelNode(const std::string& channelName);

}  // namespace rf
