#pragma once
/// The seed's recursive (Whitted) tracer: ambient + Lambert + Phong per light with distance
/// attenuation, hard shadows, mirror reflection and Snell refraction, a depth limit and the
/// rule that prunes secondary rays whose weight would not show.
#include <optional>
#include <vector>

#include "engine/integrators/bounce_cache.h"
#include "engine/materials/brdf_gltf.h"
#include "engine/integrators/integrator.h"
#include "engine/integrators/light_eval.h"
#include "engine/scene/scene.h"
#include "engine/integrators/shading_frame.h"
#include "engine/integrators/shadow_catcher.h"

namespace rf {

class WhittedTracer final : public Integrator {
public:
    /// bounceSlot: where the job keeps its bounce cache (null: the tracer builds one of its own).
    WhittedTracer(const Scene& scene, const RenderSettings& settings, SceneCacheSlot* bounceSlot = nullptr);

    /// Radiance along a primary ray (counted as primary); see Integrator::Li.
    Color Li(const Ray& r, uint64_t seed, RayStats& stats, float* coverage) const override;
    /// The packet's rays through SceneGeometry::intersectPacket, then each wanted one as Li goes on.
    void LiPacket(const Ray* rays, int n, uint64_t wanted, const uint64_t* seeds, RayStats& stats, Color* out,
                  float* coverage) const override;
    /// Only sampled indirect light draws random numbers.
    bool usesSeed() const override { return settings_.indirectSamples > 0; }

    /// Local illumination at a surface point seen along direction d (the seed's Phong formula).
    /// weight: what the result is worth in the pixel; a light whose term would count for no
    /// more than settings.minWeight there is left out, shadow ray and all.
    Color shade(const SurfaceInteraction& si, const Vec3& d, RayStats& stats, const Color& weight = Color(1.f)) const;

private:
    /// seed: the ray's sample stream (sampler.h); kNoSampleSeed for rays that must not sample
    /// indirect light themselves (the samples' own rays: one bounce, not a path).
    /// tHit (if given): the distance to what the ray met, infinity if it met nothing.
    Color trace(const Ray& r, int depth, const Color& weight, RayStats& stats, uint64_t seed,
                uint32_t skip = SceneGeometry::kNoPrim, float* tHit = nullptr) const;
    /// KHR_materials_volume: what is left of light that crossed the inside of si's volume along
    /// a ray that met something at distance t (exp(−σ·t)); the thickness at si where it met
    /// nothing (an open mesh). White where si's material is no volume there.
    Color volumeTransmittance(const SurfaceInteraction& si, float t) const;
    /// Li once the primary ray's closest hit is known (met: whether it has one).
    Color primaryLi(const Ray& r, bool met, const Hit& h, uint64_t seed, RayStats& stats, float* coverage) const;
    /// trace() once the ray's closest hit is known: through blended surfaces (alphaMode BLEND)
    /// to what lies behind them; *coverage (if given) gets the share of the ray they covered.
    Color traceHit(const Ray& r, const Hit& hit, int depth, const Color& weight, RayStats& stats, uint64_t seed,
                   float* coverage = nullptr) const;
    /// One surface's light at si, met by r: its shading, then its mirror and refracted rays.
    Color surfaceHit(const Ray& r, const SurfaceInteraction& si, int depth, const Color& weight, RayStats& stats,
                     uint64_t seed) const;
    /// surfaceHit's mirror and refracted rays at a dispersive glTF surface (KHR_materials_dispersion
    /// with transmission): each colour channel refracts at its own wavelength's index, one ray per
    /// channel, and the mirror ray weighs each channel's Fresnel. A ray that carries one channel
    /// only (its weight is 0 in the others: a ray split so before) refracts at that one's index.
    /// ng faces the incoming ray, ns is on its side (as surfaceHit has them).
    Color dispersiveRays(const Ray& r, const SurfaceInteraction& si, int depth, const Color& weight, RayStats& stats,
                         uint64_t seed, float transmission, bool entering, const Vec3& ng, const Vec3& ns) const;
    /// Blended surfaces one ray passes before the rest counts as covered (a bound on the work
    /// of a line through very many of them; each leaves its uncovered share to the next).
    static constexpr int kBlendCrossings = 64;
    /// The mirror ray from si along dir (on the side of ng it leaves to), traced at depth + 1
    /// and counted as a reflection ray; tHit as trace()'s.
    Color traceReflection(const SurfaceInteraction& si, const Vec3& ng, const Vec3& dir, int depth, const Color& weight,
                          RayStats& stats, uint64_t seed, float* tHit = nullptr) const;
    /// The glTF material model (whitted_gltf.cpp): the metallic-roughness BRDF under the lights,
    /// the environment and, for smooth surfaces, the traced mirror ray. depth: of the ray that hit.
    Color shadeGltf(const SurfaceInteraction& si, const Vec3& d, int depth, const Color& weight, RayStats& stats,
                    uint64_t seed) const;
    /// What sampled indirect light (settings.indirectSamples, indirect_light.cpp) found: the
    /// glossy radiance around the lobe and the diffuse radiance (irradiance/π), with occlusion
    /// and one bounce, in the units pbr::environmentLight takes.
    struct IndirectRadiance {
        Color specular{0.f};
        Color diffuse{0.f};
    };
    /// Samples the glossy lobe (when glossy > 0: its share of the specular light) and the diffuse
    /// lobe (when diffuse) of s at si, in place of `unshadowed` (the environment's split sum);
    /// weight: what the result is worth in the pixel.
    IndirectRadiance sampleIndirect(const SurfaceInteraction& si, const ShadingFrame& frame, const pbr::Surface& s,
                                    const Vec3& V, float glossy, bool diffuse, const IndirectRadiance& unshadowed,
                                    int depth, const Color& weight, RayStats& stats, uint64_t seed) const;
    /// The radiance the ray along dir (above the facet) from si brings back (one bounce: its hit
    /// shaded without sampling), and whether it escaped to the environment.
    Color sampleRay(const SurfaceInteraction& si, const ShadingFrame& frame, Vec3 dir, int depth, const Color& weight,
                    RayStats& stats, bool& escaped) const;
    /// What a secondary ray that meets nothing brings: the environment, else the background.
    Color missRadiance(const Vec3& d) const;
    /// What a primary ray that meets nothing shows: the environment where it is the background.
    Color primaryMiss(const Vec3& d) const;
    /// A primary ray that meets the shadow catcher at distance t: what lies behind it dimmed by
    /// the shadow, or over a transparent background no colour and the shadow as coverage.
    Color groundLi(const Ray& r, float t, RayStats& stats, float* coverage) const;
    /// The Phong (or Blinn–Phong) specular term k_spec·x^n for light direction l.
    float specular(const Material& m, int material, const Vec3& ns, const Vec3& l, const Vec3& V) const;

    const Scene& scene_;
    RenderSettings settings_;
    std::vector<float> specFloor_;  ///< per material: the Phong term is skipped below this cosine
    /// What a unit of radiance shows as after exposure (2^EV): the pruning rule compares a
    /// light's worth in the displayed picture with settings.minWeight, so a scene's units cannot
    /// prune all of its light away.
    float displayScale_ = 1.f;
    bool seeThroughShadows_ = false;  ///< some material transmits: shadow rays filter through it
    bool blending_ = false;           ///< some material blends (alphaMode BLEND): rays pass through it
    std::optional<ShadowCatcher> catcher_;  ///< --ground shadow
    std::shared_ptr<const BounceCache> bounce_;  ///< the default look's bounce light (null: none)
    /// An integrator serves one thread (renderTile makes one per tile), so its shading points
    /// share this cache of each light's last blocker without a lock.
    mutable ShadowBlockers blockers_;
};

}  // namespace rf
