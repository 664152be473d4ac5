#pragma once
/// The bones of an assimp mesh (FBX and COLLADA skins) as what a glTF skin needs: its joints
/// named by node, their inverse bind matrices and the vertices' JOINTS_n/WEIGHTS_n, so that the
/// glTF loader poses them as it poses a glTF file's skins (assimp_import.cpp writes them into
/// the model). assimp's bone is glTF's joint: aiBone::mName names the node that moves it, and
/// its mOffsetMatrix takes the mesh's space to that node's in the bind pose, which is what an
/// inverse bind matrix does; the mesh's own node transform is then ignored, as glTF ignores a
/// skinned mesh's.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <tiny_gltf.h>

struct aiMesh;
struct aiScene;

namespace rf {

struct AssimpSkin {
    /// At most this many influences per vertex (two JOINTS_n/WEIGHTS_n sets): a vertex with more
    /// keeps its largest. Every vertex's weights are divided by their sum.
    static constexpr int kMaxInfluences = 8;

    /// One per joint: the mesh's bones in their order, their names as assimp gives them. When
    /// some vertex has no weight at all, one more, empty: the node that draws the mesh, with the
    /// identity as inverse bind matrix, so that such a vertex stays where the mesh's node puts
    /// it (as Blender and assimp leave it) instead of following the first bone.
    std::vector<std::string> jointNames;
    std::vector<float> inverseBind;  ///< 16 floats a joint, column-major as glTF stores a MAT4
    int sets = 0;                    ///< JOINTS_n/WEIGHTS_n pairs (0: the mesh is not skinned)
    std::vector<uint16_t> joints;    ///< 4·sets a vertex of the mesh (unused ones 0 …)
    std::vector<float> weights;      ///< … with weight 0
    size_t verticesOverCap = 0;      ///< vertices that had more than kMaxInfluences influences
    size_t unweighted = 0;           ///< vertices no bone weighs (bound to the mesh's node)
    size_t weightsDropped = 0;       ///< weights left out: negative, non-finite or of no vertex
    std::string refused;             ///< why the bones cannot be a skin ("" when they can)
};

/// The skin of m (sets 0 when it has no bones, or refused says why its bones are unusable).
/// Time and memory linear in the mesh's vertices and weights.
AssimpSkin assimpSkin(const aiMesh& m);

/// The glTF node of a mesh with a skin or morph targets: a glTF node has one skin and one set
/// of morph weights, but each of assimp's meshes has bones and targets of its own, so each such
/// mesh is drawn by a node of its own under the one that holds it (made with the node tree).
struct OwnNode {
    int node;       ///< the glTF node that draws the mesh
    unsigned mesh;  ///< assimp's mesh
    int holder;     ///< the glTF node of assimp's node that holds the mesh
};

/// Gives each skinned mesh's node its skin: the joints are the nodes its bones name (the first
/// node of that name in nodeByName, as assimp's animation channels find theirs), so the node
/// animations already converted pose it; mat4Accessor writes the inverse bind matrices (16
/// floats each) and returns their accessor. A bone that names no node leaves the mesh in its
/// bind pose, noted, as are the weights assimpSkin left out or changed.
void makeSkins(tinygltf::Model& g, const aiScene& scene, const std::vector<AssimpSkin>& skins, const std::vector<OwnNode>& nodes,
               const std::map<std::string, int>& nodeByName, std::vector<std::string>& notes,
               const std::function<int(const std::vector<float>&)>& mat4Accessor);

}  // namespace rf
