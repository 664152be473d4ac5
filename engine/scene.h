#pragma once
/// The scene in render space: geometry, materials, lights, camera and the acceleration
/// structure over them. World position = render position + renderOrigin (kept in double, so a
/// model far from the world origin keeps its float precision).
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "bvh.h"
#include "camera.h"
#include "interaction.h"
#include "light.h"
#include "material.h"
#include "material_eval.h"
#include "mesh.h"
#include "scene_graph.h"
#include "scene_options.h"
#include "settings.h"
#include "shapes.h"
#include "texture.h"
#include "triangle.h"
#include "triangle4.h"

namespace rf {

class EnvironmentLight;

/// What a scene uses, so the renderer can leave out what it does not need.
struct SceneFeatures {
    bool reflection = false;    ///< some material reflects
    bool transmission = false;  ///< some material refracts
    bool shadows = false;       ///< some light casts shadows
    bool textures = false;      ///< some material samples a texture
    bool animated = false;      ///< some mesh hangs on an animated node
};

class Scene {
public:
    Camera camera;
    std::vector<Light> lights;
    std::vector<Material> materials;
    std::vector<Sphere> spheres;
    std::vector<Plane> planes;
    std::vector<TriangleMesh> meshes;
    TextureSet textures;  ///< shared by copies of the scene (texture.h)
    std::vector<SceneGraph> models;
    std::vector<Camera> gltfCameras;  ///< glTF models' cameras in node order, selectable as the render camera
    /// Beside each of gltfCameras: its file, and why it cannot be used ("" if it can), said
    /// when it is chosen.
    std::vector<std::pair<std::string, std::string>> gltfCameraFaults;
    Color background{0.f};
    /// Primary rays that miss give no colour and zero coverage (alpha), so the film can be laid
    /// over something else; reflections and refractions still see `background`.
    bool transparentBackground = false;
    /// Light from all around, as an equirectangular radiance image (null: none).
    std::shared_ptr<const EnvironmentLight> environment;
    /// What `environment` was made from (file empty: the built-in studio), so a saved scene
    /// file can name it again.
    EnvironmentSpec environmentSource;
    /// Primary rays that miss everything see the environment instead of `background`
    /// (secondary rays see it whenever there is one).
    bool environmentBackground = false;
    /// Render-space height of the shadow catcher of --ground shadow (shadow_catcher.h): camera
    /// rays that reach it see what lies behind it dimmed by the model's shadow. None: no ground.
    std::optional<float> shadowCatcherHeight;
    Color ambientLight{1.f};  ///< I_amb of the seed's model
    RenderSettings settings;  ///< defaults from the scene file; the CLI may override
    DVec3 renderOrigin{0.0};
    std::string sourcePath;
    /// The scene file's animation sections as parsed JSON, null without any:
    /// {"timeline": {...}, "timeline_file": path if it came from its own file, "turntable": {...}}.
    /// anim::Timeline interprets it; nothing parses or rewrites it as text again.
    std::shared_ptr<const nlohmann::json> timeline;
    std::vector<std::string> notes;  ///< warnings met while loading
    /// --animation NAME|INDEX (SceneOptions::animation): the animation every animated model
    /// plays, over the scene file's "animation"; anim::Timeline resolves it.
    std::optional<std::string> animation;

    /// Builds the acceleration structure; call after loading or after geometry changed.
    void build();
    /// Updates the BVH after mesh positions moved (topology unchanged): the tree build() made,
    /// refitted to the new boxes, or built afresh over them when the refit's SAH cost has grown
    /// past kRebuildGrowth × the built tree's. Either way a function of the positions alone
    /// (never of earlier poses), so every rank and frame order gets the same tree.
    void refit();
    static constexpr double kRebuildGrowth = 1.5;
    /// Whether the last refit() rebuilt the tree (for benchmarks and tests).
    bool lastRefitRebuilt() const { return lastRebuilt_; }
    /// Rewrites the positions of meshes on nodes from world matrices (render space), then refits.
    void applyNodeTransforms(int model, const std::vector<DMat4>& renderFromNode,
                             const std::vector<std::vector<double>>& morphWeights = {});

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
    SceneFeatures features() const;
    size_t triangleCount() const { return triVerts_.size() / 3; }
    bool usesBvh() const { return useBvh_; }
    const Bvh& bvh() const { return bvh_; }
    /// After build(): nothing else reaches into sphere i (no other sphere overlaps it, no plane
    /// cuts it; touching is fine), so a ray starting inside meets only its exit.
    bool sphereAlone(size_t i) const { return i < sphereAlone_.size() && sphereAlone_[i]; }

    /// Below this many bounded primitives, brute force beats building a BVH.
    static constexpr size_t kBvhThreshold = 8;
    static constexpr uint32_t kNoPrim = ~0u;
    static constexpr uint32_t kFromInside = 1u << 31;

private:
    bool intersectSlot(uint32_t slot, const Ray& r, const WatertightRay& wr, float& tMax, Hit& hit, uint32_t skip) const;
    /// Whether triangle prim blocks the ray before tMax as the BVH walk would find it: the
    /// leaves' test (intersectSlot's for a triangle), and its box passing the walk's box test.
    bool walkWouldBlock(uint32_t prim, const Ray& r, const WatertightRay& wr, float tMax) const;
    /// The slots of one BVH leaf in order (closest hit, or the first hit with anyHit).
    bool intersectLeaf(uint32_t first, uint32_t count, const Ray& r, const WatertightRay& wr, float& tMax, Hit& hit,
                       uint32_t skip, bool anyHit) const;
    /// The sphere (scene-wide prim id) a ray marked kFromInside starts in, or kNoPrim.
    static uint32_t insidePrim(uint32_t skip) { return (skip != kNoPrim && (skip & kFromInside)) ? skip & ~kFromInside : kNoPrim; }
    bool triangleAlphaPasses(uint32_t tri, const TriangleHit& h) const;
    /// Brute-force mode: bit i set if sphere i may be hit (a branch-free, vectorisable pre-test).
    /// *sure (if given) gets the spheres the ray certainly enters before tMax from outside,
    /// which a shadow ray can accept without the exact root.
    uint32_t sphereCandidates(const Ray& r, float tMax, uint32_t* sure = nullptr) const;
    void fillSlotData();
    /// Fills sphereAlone_ (after the BVH, which it queries when there is one).
    void findAloneSpheres();

    Bvh bvh_;
    bool useBvh_ = false;
    /// The tree build() made and its SAH cost: refit() starts from it whenever it rebuilt.
    Bvh builtBvh_;
    double builtCost_ = 0.0;
    bool lastRebuilt_ = false;
    /// Triangles and spheres as build() counted them: the hot paths' primitive-id ranges
    /// (triangles first, then spheres, then planes), read once instead of from the vectors.
    uint32_t nTri_ = 0, nSph_ = 0;
    std::vector<Vec3> triVerts_;     ///< three per triangle, in BVH-independent order
    std::vector<uint32_t> triMesh_;  ///< mesh of each triangle
    std::vector<uint32_t> triLocal_; ///< triangle index within its mesh
    std::vector<uint8_t> meshMasked_; ///< mesh needs an alpha test during traversal
    /// Per sphere: no other primitive reaches into it (touching is fine), so a ray starting
    /// inside meets nothing before the sphere's own exit. Always 0 in scenes with triangles.
    std::vector<uint8_t> sphereAlone_;
    bool anyMasked_ = false;
    /// Primitive data in BVH leaf order (identity order without a BVH), so traversal reads
    /// leaves contiguously: the primitive id and, for triangles, the three vertices.
    std::vector<uint32_t> slotPrim_;
    std::vector<Vec3> slotVerts_;
    LeafTriangles leafTris_;  ///< the same triangles, four per block, for the leaf pre-test
    /// Brute-force sphere pre-test, structure of arrays padded to kBvhThreshold lanes.
    float sphX_[kBvhThreshold] = {}, sphY_[kBvhThreshold] = {}, sphZ_[kBvhThreshold] = {};
    float sphReach_[kBvhThreshold] = {};  ///< radius plus its centre's share of the float error
    float sphInner_[kBvhThreshold] = {};  ///< radius minus it
};

/// Base colour of the scene's material at a surface point (material_eval.h's baseColor).
inline Color baseColor(const Scene& scene, const SurfaceInteraction& si, float* alpha = nullptr) {
    return baseColor(scene.materials[si.material], scene.textures, scene.renderOrigin, si, alpha);
}

}  // namespace rf
