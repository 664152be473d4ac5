#pragma once
/// glTF 2.0 skinning (linear blend, §3.7.3): joint matrices from the joints' posed transforms,
/// and each vertex moved by the weighted sum of its joints' matrices after its morph targets.
/// Also the rigid case (one node matrix), so both kinds of moving mesh are posed by one rule.
#include <cstddef>
#include <vector>

#include "engine/geometry/mesh.h"
#include "engine/geometry/scene_graph.h"

namespace rf {

/// renderFromNode[joint] · inverseBind for every joint of the skin: the matrices that take a
/// vertex from the mesh's bind space to render space. A joint outside renderFromNode (the
/// loader refuses those) gets the identity.
std::vector<DMat4> jointMatrices(const Skin& skin, const std::vector<DMat4>& renderFromNode);

/// Σ weight · joint matrix over the vertex's influences (its skin matrix).
DMat4 skinMatrix(const TriangleMesh& mesh, size_t vertex, const std::vector<DMat4>& joints);

/// Rewrites a moving mesh's positions, normals and tangents from its object-space copies:
/// morph targets at `weights` first (null: none; POSITION, NORMAL and TANGENT deltas), then the
/// skin's joint matrices when mesh.skin ≥ 0 (`joints`), else `renderFromNode`. Normals go by
/// the inverse transpose and are unit length; tangents by the linear part, unit length, their
/// w flipped where the matrix mirrors (as the loader does for baked meshes). Where it mirrors,
/// mesh.mirrored (rigid) or mesh.mirroredVertices (skinned) say so: the faces turn round.
void poseMesh(TriangleMesh& mesh, const DMat4& renderFromNode, const std::vector<DMat4>* joints,
              const std::vector<double>* weights);

}  // namespace rf
