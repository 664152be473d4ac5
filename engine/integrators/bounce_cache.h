#pragma once
/// Bounce light of the default look: one deterministic, noise-free diffuse bounce of the scene's
/// punctual lights and emission, cached on the surfaces (RenderSettings::bounce).
///
/// A radiosity-like cache over a point cloud. Points are spread over the glTF surfaces by area
/// (bounce_points.h). Once per geometry, each gathers its hemisphere with a fixed set of
/// cosine-distributed rays; where a ray lands, the kernel weights of the points around it are
/// kept, so the gather becomes a sparse transfer matrix from the points' outgoing radiance to
/// their incoming bounce. The mesh vertices (and a regular grid over triangles larger than the
/// kernel) likewise keep the weights of the points around them. Each time the lights change,
/// one shadow ray per point and light gives the points' direct outgoing radiance, two sparse
/// products give the bounce at the points (twice over: two bounces) and at the vertices, and
/// shading interpolates the vertices' values across each triangle.
///
/// Nothing in it depends on the camera, the pixel or the sample: in a turntable around a lit
/// model it is built once, and every frame sees the same bounce at the same surface point. It
/// is a function of the scene alone, built in a fixed order, so it is the same on every rank and
/// at every thread count.
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/geometry/interaction.h"
#include "engine/util/settings.h"
#include "engine/util/stats.h"

namespace rf {

class Scene;
struct SceneCacheSlot;
struct BounceGeometry;

class BounceCache {
public:
    explicit BounceCache(std::shared_ptr<const BounceGeometry> geometry) : geometry_(std::move(geometry)) {}
    /// The bounce arriving at a mesh point, as irradiance/π (the unit pbr::environmentLight's
    /// diffuse radiance takes), on side `side` (+1: the side the surface's normals point to).
    /// Zero on surfaces outside the cache (not glTF, glass, the back of a one-sided material).
    Color at(const Scene& scene, const SurfaceInteraction& si, float side) const;
    /// The same at cache point i (tests, the report).
    Color atPoint(size_t i) const { return i < pointBounce_.size() ? pointBounce_[i] : Color(0.f); }
    const BounceGeometry& geometry() const { return *geometry_; }

    /// Lights the cache's geometry with the scene's lights (on `threads` threads).
    void light(const Scene& scene, int threads);
    /// The shadow rays the last light() traced.
    uint64_t rays() const { return rays_; }

private:
    std::shared_ptr<const BounceGeometry> geometry_;
    std::vector<Color> pointBounce_;  ///< bounce arriving at each point
    std::vector<Color> nodeBounce_;   ///< bounce arriving at each node
    uint64_t rays_ = 0;
};

/// Builds the geometric half of the cache: about `points` surface points, their gather and the
/// mesh nodes' weights (on `threads` threads). Null when the scene has no bounce surface.
std::shared_ptr<const BounceGeometry> buildBounceGeometry(const Scene& scene, uint32_t points, int threads);

/// The scene's bounce cache for these settings, or null when there is none to use
/// (settings.bounce 0, sampled indirect light, no glTF surface, neither lights nor emission).
/// Built on `threads` threads when the scene's geometry or lights changed since the last call
/// with this slot (the job's: RenderView::bounceSlot; the cache is kept there, keyed by both),
/// so a turntable that moves only the camera builds it once. Null slot: none. Thread-safe.
/// spent (if given) counts the rays this call traced to build or light it (RayStats::bounce).
std::shared_ptr<const BounceCache> bounceCache(const Scene& scene, const RenderSettings& settings, SceneCacheSlot* slot,
                                               int threads, RayStats* spent = nullptr);

/// Whether the scene has what bounce light needs: a surface it lights (bounce_points.h's
/// bounceSurface) and lights or emission to bounce.
bool bounceApplies(const Scene& scene);

/// Whether bounce light is left out of this film because its geometry moves
/// (RenderSettings::bounceMoving): settings ask for it, the scene has lights and moving meshes.
bool bounceLeftOutForMotion(const Scene& scene, const RenderSettings& settings);

/// The number of surface points of settings.bounce (which counts thousands).
uint32_t bouncePoints(const RenderSettings& settings);

}  // namespace rf
