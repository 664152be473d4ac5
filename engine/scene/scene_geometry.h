#pragma once
/// The scene's geometry in render space: its primitives (spheres, planes, triangle meshes and
/// the models' node graphs they hang on), the two-level acceleration structure over them, and
/// every ray query. A ray's path reads top-down from here: intersect / intersectPacket /
/// occluded (scene_geometry.cpp) walk the trees (bvh.h) and test the leaves' triangles and
/// spheres (triangle.h, shapes.h); build, refit and posing are in scene_accel.cpp.
/// Scene (scene.h) owns one; it needs nothing else of the scene but the materials' alpha,
/// handed to build().
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "engine/geometry/bvh.h"
#include "engine/geometry/interaction.h"
#include "engine/geometry/mesh.h"
#include "engine/geometry/scene_graph.h"
#include "engine/geometry/scene_instance.h"
#include "engine/geometry/shapes.h"
#include "engine/geometry/triangle.h"
#include "engine/geometry/triangle4.h"
#include "engine/materials/material.h"
#include "engine/materials/texture.h"

namespace rf {

class SceneGeometry {
public:
    std::vector<Sphere> spheres;
    std::vector<Plane> planes;
    std::vector<TriangleMesh> meshes;
    std::vector<SceneGraph> models;  ///< the glTF models' node graphs and skins, which pose meshes

    /// Builds the acceleration structure; call after loading or after geometry changed. The
    /// masked-triangle test reads materials and textures (alphaMode, alpha, cut-off, base-colour
    /// texture): build() keeps a copy of the materials and a share of the textures when some mesh
    /// is masked, so a material's alpha changed later takes another build(), as its alphaMode
    /// always did. Two levels (scene_instance.h): the meshes that never move and the spheres in one tree, each
    /// skinned or morphed mesh in its own, each animated node's rigid meshes in one tree of
    /// their object space, and a top level over them; a scene with nothing that moves is the
    /// one tree alone.
    void build(const std::vector<Material>& materials, const TextureSet& textures);
    /// The materials' alpha, cut-off and base-colour transform changed (an animation keys them):
    /// the masked-triangle test reads these from now on. No tree changes.
    void updateMaterials(const std::vector<Material>& materials) {
        if (anyMasked_) maskMaterials_ = materials;
    }
    /// A number no other build(), refit() or moving applyNodeTransforms() of any scene in this
    /// process has given: what the bounce cache keys its geometry by.
    uint64_t version() const { return version_; }
    /// Updates every tree after mesh positions moved (topology unchanged): each render-space
    /// tree refitted from the one build() made, or built afresh over the new boxes when the
    /// refit's SAH cost has grown past kRebuildGrowth × the built tree's; rigid instances take
    /// their meshes' renderFromObject. Either way a function of the positions alone (never of
    /// earlier poses), so every rank and frame order gets the same trees.
    void refit();
    /// Measured (docs/performance.md, anim_bench --rule): refits at SAH ratios up to 2.0
    /// rendered the benchmark's skinned strip a few per cent slower than fresh trees (about 7%
    /// on average at 1.7-2.0), while its rebuild (114k triangles) cost more than a rank's whole
    /// share of a 640x360 frame; at 1.5 the rule rebuilt 8 frames in 120 for no visible gain.
    static constexpr double kRebuildGrowth = 2.0;
    /// The rule's threshold this geometry uses (kRebuildGrowth; benchmarks vary it to measure it).
    double rebuildGrowth = kRebuildGrowth;
    /// Whether the last refit() or applyNodeTransforms() rebuilt a tree (benchmarks, tests).
    bool lastRefitRebuilt() const { return lastRebuilt_; }
    /// What the last applyNodeTransforms() cost, for benchmarks: posing (morph, skin, the
    /// meshes' render-space triangles) and the trees (anchor trees built, refits, rebuilds, the
    /// top level), in seconds; anchor trees it built; the largest SAH ratio of a refit.
    struct UpdateCost {
        double poseS = 0.0, treeS = 0.0;
        int anchorsBuilt = 0;
        double sahRatio = 0.0;
    };
    const UpdateCost& lastUpdateCost() const { return lastCost_; }
    /// One of a few fixed poses of a looping clip (anim/ spaces them evenly over it), nearest the
    /// frame's pose: a deforming mesh's tree is that pose's tree refitted, rather than the rest
    /// pose's, so it stays good over the whole clip. Built the first time a frame needs it and
    /// kept; a function of the clip and index alone, so the frame's tree still depends on the
    /// frame alone, whatever order frames come in.
    struct PoseAnchor {
        int clip = 0;   ///< which clip the anchors belong to (its animation index)
        int index = 0;  ///< which anchor
        /// The anchor's node matrices and morph weights, as applyNodeTransforms takes them.
        std::function<void(std::vector<DMat4>&, std::vector<std::vector<double>>&)> pose;
    };
    /// A node matrix of zeros (its last row too, which an affine matrix has as (0, 0, 0, 1)) hides
    /// the node's meshes this frame: they collapse to a point, skinned ones too, and are never hit.
    /// Rewrites the positions of meshes on nodes from world matrices (render space), and updates
    /// only what they move: their deforming trees (refitted from anchor's tree when given), their
    /// rigid instances' matrices, the top level.
    void applyNodeTransforms(int model, const std::vector<DMat4>& renderFromNode,
                             const std::vector<std::vector<double>>& morphWeights = {}, const PoseAnchor* anchor = nullptr);

    /// Closest hit in (0, r.tMax). skip (see skipFor): a convex primitive (sphere, plane) the
    /// ray leaves on its outer side, which it cannot meet again and so is not tested; or
    /// kFromInside | sphere id for a ray entering that sphere, which meets it only at its exit.
    bool intersect(const Ray& r, Hit& hit, uint32_t skip = kNoPrim) const;
    /// intersect() for n camera rays of neighbouring pixels (at most Bvh::kPacketMax; no skip):
    /// traced together through the BVH (Bvh::traversePacket) where they share an origin.
    /// met[i]: whether ray i hit, hits[i] its closest hit. Each ray is tested against the same
    /// primitives with the same float operations as intersect() gives it; only where two
    /// surfaces tie within rounding can the visiting order pick the other, so callers trace
    /// the same packets whatever the tiling (render.cpp: aligned pixel blocks).
    void intersectPacket(const Ray* rays, int n, Hit* hits, bool* met) const;
    /// Any hit in (0, tMax): the shadow-ray query. lastBlocker (may be null): a triangle to try
    /// before the BVH, updated to the one that blocked this ray. Shadow rays of neighbouring
    /// pixels towards one light are mostly blocked by the same triangle; trying it first with
    /// the leaves' own test changes what the query costs, never its answer.
    bool occluded(const Ray& r, float tMax, uint32_t skip = kNoPrim, uint32_t* lastBlocker = nullptr) const;
    /// What a ray spawned at si in direction dir knows about its own primitive: si's sphere is
    /// skipped when dir points out of it and marked kFromInside when dir points in; si's plane is
    /// always skipped; kNoPrim otherwise (triangles).
    uint32_t skipFor(const SurfaceInteraction& si, const Vec3& dir) const;
    SurfaceInteraction interaction(const Ray& r, const Hit& hit) const;

    Aabb bounds() const;  ///< bounds of spheres and meshes (planes are infinite)
    size_t triangleCount() const { return triVerts_.size() / 3; }
    bool usesBvh() const { return useBvh_; }
    /// The first instance's tree: the whole geometry's when nothing moves (an empty tree without a BVH).
    const Bvh& bvh() const { return instances_.empty() ? emptyBvh_ : instances_[0].bvh; }
    const std::vector<SceneInstance>& instances() const { return instances_; }
    /// Whether rays walk a top level over several instances (false: one tree, or none).
    bool twoLevel() const { return twoLevel_; }
    /// After build(): nothing else reaches into sphere i (no other sphere overlaps it, no plane
    /// cuts it; touching is fine), so a ray starting inside meets only its exit.
    bool sphereAlone(size_t i) const { return i < sphereAlone_.size() && sphereAlone_[i]; }

    /// Below this many bounded primitives, brute force beats building a BVH.
    static constexpr size_t kBvhThreshold = 8;
    /// Up to this many instances a camera packet walks each instance's tree (intersectPacket).
    static constexpr size_t kPacketInstances = 4;
    static constexpr uint32_t kNoPrim = ~0u;
    static constexpr uint32_t kFromInside = 1u << 31;

private:
    bool intersectSlot(uint32_t slot, const Ray& r, const WatertightRay& wr, float& tMax, Hit& hit, uint32_t skip) const;
    /// Whether triangle prim blocks the ray before tMax as the BVH walk would find it: the
    /// leaves' test (intersectSlot's for a triangle), and its box passing the walk's box test.
    bool walkWouldBlock(uint32_t prim, const Ray& r, const WatertightRay& wr, float tMax) const;
    /// The slots of one leaf of instance in (first: its local slot) in order (closest hit, or
    /// the first hit with anyHit); r and wr in the instance's space.
    bool intersectLeaf(const SceneInstance& in, uint32_t first, uint32_t count, const Ray& r, const WatertightRay& wr,
                       float& tMax, Hit& hit, uint32_t skip, bool anyHit) const;
    /// Walks the top level and the instances' trees (or the one tree) front to back:
    /// leaf(instance, r in its space, first local slot, count, tMax) tests one leaf.
    template <typename LeafFn>
    bool walk(const Ray& r, float tMax, bool anyHit, LeafFn&& leaf) const;
    /// The sphere (scene-wide prim id) a ray marked kFromInside starts in, or kNoPrim.
    static uint32_t insidePrim(uint32_t skip) { return (skip != kNoPrim && (skip & kFromInside)) ? skip & ~kFromInside : kNoPrim; }
    bool triangleAlphaPasses(uint32_t tri, const TriangleHit& h) const;
    /// Brute-force mode: bit i set if sphere i may be hit (a branch-free, vectorisable pre-test).
    /// *sure (if given) gets the spheres the ray certainly enters before tMax from outside,
    /// which a shadow ray can accept without the exact root.
    uint32_t sphereCandidates(const Ray& r, float tMax, uint32_t* sure = nullptr) const;
    void fillSlotData();
    /// scene_accel.cpp: the instances and the top level (build), one instance's tree refitted
    /// or rebuilt and its slots filled, a rigid instance moved, the top level over the boxes.
    void buildInstances();
    /// base: the tree to refit (null: the one build() made), its SAH cost and which it is
    /// (SceneInstance::bvhFrom).
    void refitInstance(SceneInstance& in, const Bvh* base = nullptr, double baseCost = 0.0,
                       std::pair<int, int> baseKey = SceneInstance::kNoTree);
    /// Poses model's moving meshes (all, or those of instance only) from node matrices; marks
    /// each in moved (if given) and gathers its triangles.
    void poseModel(int model, const std::vector<DMat4>& renderFromNode, const std::vector<std::vector<double>>& morphWeights,
                   const SceneInstance* only, std::vector<uint8_t>* moved);
    /// The anchor's tree for a deforming instance, built (posing its meshes at the anchor) when
    /// missing; anchorPose caches the anchor's matrices between instances.
    const SceneInstance::AnchorTree& anchorTree(SceneInstance& in, const PoseAnchor& anchor, std::vector<DMat4>& anchorNodes,
                                                std::vector<std::vector<double>>& anchorWeights);
    /// fillSlots, then buildLeafTriangles.
    void fillInstanceSlots(SceneInstance& in);
    /// The instance's slotPrim_ and slotVerts_ in its tree's leaf order.
    void fillSlots(SceneInstance& in);
    /// Its leaves' triangles four at a time, from its slots.
    void buildLeafTriangles(SceneInstance& in);
    void placeRigid(SceneInstance& in);
    void buildTopLevel();
    /// triVerts_ of mesh m from its positions.
    void gatherTriangles(uint32_t m);
    /// Fills sphereAlone_ (after the BVH, which it queries when there is one).
    void findAloneSpheres();

    bool useBvh_ = false;
    std::vector<SceneInstance> instances_;
    Bvh top_;                 ///< over the boxes of the instances not hidden; empty unless twoLevel_
    std::vector<uint32_t> topInstance_;  ///< top_'s primitives: those instances
    bool twoLevel_ = false;
    uint64_t version_ = 0;
    bool lastRebuilt_ = false;
    UpdateCost lastCost_;
    Bvh emptyBvh_;
    std::vector<Aabb> scratchBoxes_;  ///< refits' primitive boxes, kept to spare the allocation
    /// Triangles and spheres as build() counted them: the hot paths' primitive-id ranges
    /// (triangles first, then spheres, then planes), read once instead of from the vectors.
    uint32_t nTri_ = 0, nSph_ = 0;
    std::vector<Vec3> triVerts_;     ///< three per triangle, in BVH-independent order
    std::vector<uint32_t> triMesh_;  ///< mesh of each triangle
    std::vector<uint32_t> triLocal_; ///< triangle index within its mesh
    std::vector<uint32_t> meshPrimBegin_;  ///< first triangle of each mesh (its triangles are consecutive)
    std::vector<uint32_t> primInstance_;   ///< instance of each triangle and sphere (with a BVH)
    std::vector<uint8_t> meshMasked_; ///< mesh needs an alpha test during traversal
    /// Per sphere: no other primitive reaches into it (touching is fine), so a ray starting
    /// inside meets nothing before the sphere's own exit. Always 0 in scenes with triangles.
    std::vector<uint8_t> sphereAlone_;
    bool anyMasked_ = false;
    /// What triangleAlphaPasses reads, as build() was given it (empty unless anyMasked_).
    std::vector<Material> maskMaterials_;
    TextureSet maskTextures_;
    /// Primitive data in BVH leaf order (identity order without a BVH), so traversal reads
    /// leaves contiguously: the primitive id and, for triangles, the three vertices.
    std::vector<uint32_t> slotPrim_;
    std::vector<Vec3> slotVerts_;  ///< in the instance's space (object space for a rigid one)
    /// Brute-force sphere pre-test, structure of arrays padded to kBvhThreshold lanes.
    float sphX_[kBvhThreshold] = {}, sphY_[kBvhThreshold] = {}, sphZ_[kBvhThreshold] = {};
    float sphReach_[kBvhThreshold] = {};  ///< radius plus its centre's share of the float error
    float sphInner_[kBvhThreshold] = {};  ///< radius minus it
};

}  // namespace rf
