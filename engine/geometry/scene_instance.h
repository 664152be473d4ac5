#pragma once
/// The bottom level of the scene's two-level acceleration structure (SceneGeometry::build): one BVH
/// over a group of the scene's primitives and how rays reach it, as Embree's and pbrt-v4's
/// instances are. Three kinds, by how the group moves over a film:
/// - Static: the meshes that never move, and every sphere, in render space; built once.
/// - Deforming: a skinned or morphed mesh's triangles in render space; refitted each frame
///   from the tree build() made, rebuilt when the refit has degraded it (SceneGeometry::kRebuildGrowth).
/// - Rigid: the meshes of one animated node, in the node's object space; the tree is built
///   once and kept for the whole film, and each frame only the node's matrix changes: rays
///   are taken into object space for it.
/// The top level is a BVH over the instances' render-space boxes, rebuilt each frame (there
/// are few). A scene of one untransformed instance has no top level: rays enter it directly.
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "engine/geometry/bvh.h"
#include "engine/geometry/ray.h"
#include "engine/geometry/triangle4.h"

namespace rf {

struct SceneInstance {
    enum class Kind : uint8_t { Static, Deforming, Rigid };
    Kind kind = Kind::Static;
    int model = -1, node = -1;    ///< Deforming, Rigid: the model and node that pose it
    std::vector<uint32_t> meshes;  ///< SceneGeometry::meshes in it
    std::vector<uint32_t> prims;   ///< its primitives (scene-wide ids), the order its boxes are built in
    uint32_t slotBase = 0;         ///< its slots in the scene's slot arrays: [slotBase, slotBase + prims.size())
    Bvh bvh;                       ///< the tree rays walk (slot order = bvh.primIndex() into prims)
    Bvh built;                     ///< Deforming: the tree build() made, where every refit starts
    double builtCost = 0.0;        ///< its SAH cost (Bvh::sahCost)
    bool lastRebuilt = false;      ///< the last update rebuilt bvh instead of refitting it
    /// Deforming: trees built over fixed poses of a looping clip (SceneGeometry::PoseAnchor), keyed by
    /// (clip, anchor), each with its SAH cost; a frame's tree is the nearest anchor's refitted.
    struct AnchorTree {
        Bvh tree;  ///< topology only (dropWideNodes)
        double cost = 0.0;
    };
    std::map<std::pair<int, int>, AnchorTree> anchors;
    double lastSahRatio = 0.0;     ///< the last refit's SAH cost over its starting tree's
    /// Deforming: which starting tree bvh was last refitted from ((-1, -1): built; (clip,
    /// anchor): that anchor's; kNoTree after a rebuild). A refit from the same one again
    /// overwrites every box in place instead of copying the tree first: the same result.
    static constexpr std::pair<int, int> kNoTree{-2, -2}, kBuiltTree{-1, -1};
    std::pair<int, int> bvhFrom = kNoTree;
    LeafTriangles leafTris;        ///< its leaves' triangles, four at a time (local slots)
    /// Rigid: rays reach the object-space tree through objectFromRender (double; applied to a
    /// ray in double and rounded once). Its inverse, renderFromObject, is the node's matrix.
    bool transformed = false;
    DMat4 objectFromRender{1.0};
    /// Nothing of it can be hit this frame (a node scaled to zero): the top level leaves it out.
    bool hidden = false;
    Aabb box;                      ///< render-space bounds for the top level

    /// r in the instance's space: the same parameter t reaches the same point (d is not
    /// renormalized), so hits of different instances compare by t.
    Ray toObject(const Ray& r) const {
        Ray o = r;
        o.o = Vec3(glm::dvec3(objectFromRender * glm::dvec4(glm::dvec3(r.o), 1.0)));
        o.d = Vec3(glm::dmat3(objectFromRender) * glm::dvec3(r.d));
        return o;
    }
};

}  // namespace rf
