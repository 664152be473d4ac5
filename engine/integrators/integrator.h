#pragma once
/// The tracer seam: "radiance along a ray", after pbrt-v4's RayIntegrator::Li and Mitsuba 3's
/// Integrator::sample(). renderTile generates camera rays and asks an Integrator for their
/// radiance; which integrator runs is part of RenderSettings, so it travels with the job to
/// every rank. Material models (the seed's Phong, glTF's metallic-roughness) live inside an
/// integrator's shading, not beside it as second renderers.
#include <memory>

#include "engine/geometry/ray.h"
#include "engine/util/settings.h"
#include "engine/util/stats.h"
#include "engine/util/vec_math.h"

namespace rf {

class Scene;
struct SceneCacheSlot;

/// One instance serves one thread at a time (renderTile makes one per tile), so an
/// implementation may keep caches that change what its queries cost, never what they answer.
class Integrator {
public:
    virtual ~Integrator() = default;
    /// Radiance arriving at the camera along primary ray r; counts the rays it traces in stats.
    /// seed (sampler.h's sampleSeed of frame, pixel and sample) drives every random choice the
    /// integrator makes along the ray, so a pixel is the same on any rank and thread.
    /// *coverage (if not null) gets the sample's share of the pixel's alpha: 1 where r met
    /// geometry, 0 where it missed, the shadow's strength where it met a shadow catcher over a
    /// transparent background. With a transparent background a primary ray that misses brings
    /// no radiance, and the radiance is premultiplied by the coverage.
    virtual Color Li(const Ray& r, uint64_t seed, RayStats& stats, float* coverage) const = 0;
    /// Li for the n primary rays of one packet (neighbouring pixels' rays of one sample, at most
    /// 64): out[i] and coverage[i] (if coverage is not null) are set for each ray whose bit is
    /// set in `wanted`; the others are in the packet only so that it is the same whichever
    /// pixels a caller wants (an implementation may trace them, never shade them). By default
    /// Li one ray at a time; an integrator may trace the packet's primary rays together.
    virtual void LiPacket(const Ray* rays, int n, uint64_t wanted, const uint64_t* seeds, RayStats& stats, Color* out,
                          float* coverage) const {
        for (int i = 0; i < n; ++i)
            if ((wanted >> i) & 1u) out[i] = Li(rays[i], seeds[i], stats, coverage ? coverage + i : nullptr);
    }
    /// False if Li makes no random choice with its seed: the caller may then pass
    /// kNoSampleSeed and skip hashing one per sample.
    virtual bool usesSeed() const { return true; }
};

/// The integrator settings.integrator names, over scene (which must outlive it). bounceSlot: where
/// the job keeps its bounce cache (RenderView::bounceSlot; null: the integrator builds its own).
std::unique_ptr<Integrator> makeIntegrator(const Scene& scene, const RenderSettings& settings,
                                           SceneCacheSlot* bounceSlot = nullptr);

}  // namespace rf
