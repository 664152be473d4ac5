#pragma once
/// The seed's recursive (Whitted) tracer: ambient + Lambert + Phong per light with distance
/// attenuation, hard shadows, mirror reflection and Snell refraction, a depth limit and the
/// rule that prunes secondary rays whose weight would not show.
#include "scene.h"
#include "stats.h"

namespace rf {

class WhittedTracer {
public:
    WhittedTracer(const Scene& scene, const RenderSettings& settings);

    /// Radiance along a primary ray (counted as primary). *hit (if given): whether it met
    /// geometry. With a transparent background a miss gives black.
    Color tracePrimary(const Ray& r, RayStats& stats, bool* hit = nullptr) const;

    /// Local illumination at a surface point seen along direction d (the seed's Phong formula).
    /// weight: what the result is worth in the pixel; a light whose term would count for no
    /// more than settings.minWeight there is left out, shadow ray and all.
    Color shade(const SurfaceInteraction& si, const Vec3& d, RayStats& stats, const Color& weight = Color(1.f)) const;

    /// Base colour of the material at the surface point (checker, texture, factor).
    Color baseColor(const SurfaceInteraction& si, float* alpha = nullptr) const;

private:
    Color trace(const Ray& r, int depth, const Color& weight, RayStats& stats, uint32_t skip = Scene::kNoPrim) const;
    /// trace() once the ray's closest hit is known.
    Color traceHit(const Ray& r, const Hit& hit, int depth, const Color& weight, RayStats& stats) const;

    const Scene& scene_;
    RenderSettings settings_;
    std::vector<float> specFloor_;  ///< per material: the Phong term is skipped below this cosine
};

}  // namespace rf
