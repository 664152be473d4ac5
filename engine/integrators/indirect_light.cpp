// Sampled indirect light of the glTF material model. The default (indirectSamples 0) lights a
// surface with the environment's split sum, unshadowed: noise-free, but the underside of a
// sphere on a floor gets the whole sky and none of the floor. With N samples per lobe, rays are
// traced against the scene: those that escape keep the split sum's value in proportion to the
// environment light they found unblocked (a ratio estimator: exactly the default where nothing
// is in the way, so open surfaces stay noise-free), and those that hit bring back the surface
// they met, shaded as the default shades it (direct light, emission, split sum): one bounce.
// The tracer's half of RenderSettings::indirectSamples (WhittedTracer::sampleIndirect); the
// sample points and directions are hemisphere.h's.
#include "engine/scene/env_lighting.h"
#include "engine/lights/exposure.h"
#include "engine/materials/hemisphere.h"
#include "engine/integrators/light_eval.h"
#include "engine/util/sampler.h"
#include "engine/integrators/whitted.h"

namespace rf {

namespace {

/// The brightest a bounce sample may bring back (max component, radiance at 0 EV).
constexpr float kBounceClamp = 10.f;

/// Sums of one lobe's samples: weight, weighted radiance of what was hit, and the environment
/// light (luminance) seen unblocked and in all.
struct LobeSums {
    float weight = 0.f;
    Color hit{0.f};
    float envOpen = 0.f, envAll = 0.f;
    Color escaped{0.f};  ///< weighted radiance of the rays that escaped (used without environment)

    /// The lobe's radiance: the environment's unshadowed value × the share of its light that
    /// was unblocked, plus what the hits brought. Without an environment, the plain mean.
    Color radiance(const Color& unshadowed, bool environment) const {
        if (!(weight > 0.f)) return unshadowed;
        const Color bounce = hit / weight;
        if (!environment) return bounce + escaped / weight;
        const float open = envAll > 0.f ? envOpen / envAll : 0.f;
        return unshadowed * open + bounce;
    }
};

}  // namespace

Color WhittedTracer::sampleRay(const SurfaceInteraction& si, const ShadingFrame& frame, Vec3 dir, int depth,
                               const Color& weight, RayStats& stats, bool& escaped) const {
    const uint32_t skip = scene_.geometry.skipFor(si, dir);
    Ray r;
    // A facet lying in an axis plane has no rounding error across it (pError 0 along its
    // normal), yet a ray starting exactly on it can meet it again at t ≈ 1e-7 (the watertight
    // test rounds in the other axes): the bound is padded by the point's own scale.
    const Vec3 pad(gamma(7) * maxComponent(absComponents(si.p)));
    r.o = skip == si.prim ? si.p : offsetRayOrigin(si.p, si.pError + pad, frame.ng, dir);
    r.d = dir;
    r.coneWidth = si.coneWidth;
    r.coneSpread = si.coneSpread;
    ++stats.indirect;
    Hit hit;
    escaped = !scene_.geometry.intersect(r, hit, skip);
    if (escaped) return missRadiance(dir);
    return traceHit(r, hit, depth + 1, weight, stats, kNoSampleSeed);
}

WhittedTracer::IndirectRadiance WhittedTracer::sampleIndirect(const SurfaceInteraction& si, const ShadingFrame& frame,
                                                              const pbr::Surface& s, const Vec3& V, float glossy,
                                                              bool diffuse, const IndirectRadiance& unshadowed,
                                                              int depth, const Color& weight, RayStats& stats,
                                                              uint64_t seed) const {
    const uint32_t n = uint32_t(settings_.indirectSamples);
    const bool env = scene_.environment != nullptr;
    SampleRng rng(seed);
    Vec3 t, b;
    orthonormalBasis(frame.ns, t, b);
    const float nv = std::max(glm::dot(frame.ns, V), 1e-4f);
    // One sample's direction in world space, folded above the facet (a bent shading normal can
    // put part of its hemisphere below the surface, where a ray would start inside).
    auto toWorld = [&](const Vec3& l) {
        Vec3 w = l.x * t + l.y * b + l.z * frame.ns;
        const float below = glm::dot(w, frame.ng);
        if (below <= 0.f) w = glm::normalize(w - 2.f * below * frame.ng);
        return w;
    };
    // blur: the roughness of the prefiltered environment that weighs the occlusion ratio.
    auto add = [&](LobeSums& sums, const Vec3& dir, float w, const Color& worth, float blur) {
        bool escaped = false;
        Color L = sampleRay(si, frame, dir, depth, worth * w, stats, escaped);
        sums.weight += w;
        if (escaped) {
            sums.escaped += w * L;
        } else {
            // Cycles' default "clamp indirect" (10): a bounce off a highlight is a firefly.
            const float peak = maxComponent(L);
            if (peak > kBounceClamp) L *= kBounceClamp / peak;
            sums.hit += w * L;
        }
        if (env) {
            const float y = luminance(scene_.environment->specular(dir, blur));
            sums.envAll += w * y;
            if (escaped) sums.envOpen += w * y;
        }
    };
    IndirectRadiance out = unshadowed;
    if (glossy > 0.f) {
        // GGX half vectors about ns (the lobe for the actual view, not the split sum's n = v):
        // weights n·l, the prefiltered radiance's own convention (env_lighting.cpp).
        const Vec2 rot(rng.next(), rng.next());
        const float alpha = std::max(pbr::alphaFromRoughness(s.roughness), pbr::kMinAlpha);
        const Color worth = weight * glossy * s.occlusion * pbr::specularAlbedo(s, nv) / float(n);
        LobeSums sums;
        for (uint32_t i = 0; i < n; ++i) {
            const Vec2 u = stratifiedPoint(i, n, rot);
            const Vec3 h = toWorld(pbr::sampleGgxHalfVector(alpha, u.x, u.y));
            const Vec3 l = 2.f * glm::dot(V, h) * h - V;
            const float nl = glm::dot(frame.ns, l);
            if (nl <= 0.f || glm::dot(l, frame.ng) <= 0.f) continue;
            add(sums, l, nl, worth, s.roughness);
        }
        out.specular = sums.radiance(unshadowed.specular, env);
    }
    if (diffuse) {
        const Vec2 rot(rng.next(), rng.next());
        const Color worth = weight * s.occlusion * (1.f - s.metallic) * s.baseColor / float(n);
        LobeSums sums;
        for (uint32_t i = 0; i < n; ++i) add(sums, toWorld(cosineHemisphere(stratifiedPoint(i, n, rot))), 1.f, worth, 1.f);
        out.diffuse = sums.radiance(unshadowed.diffuse, env);
    }
    return out;
}

}  // namespace rf
