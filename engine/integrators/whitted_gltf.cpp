// The glTF metallic-roughness material model of the Whitted tracer (the seed's Phong model is
// in whitted.cpp): same rays, shadows, depth limit and pruning, another BRDF.
#include "engine/materials/brdf_gltf.h"
#include "engine/materials/brdf_sheen.h"
#include "engine/scene/env_lighting.h"
#include "engine/integrators/light_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/materials/optics.h"
#include "engine/util/sampler.h"
#include "engine/integrators/shading_frame.h"
#include "engine/integrators/whitted.h"

namespace rf {

namespace {
/// Below this roughness a surface traces its mirror ray, so it reflects the scene, not only the
/// environment; the traced share fades out linearly towards it (a sharp reflection of a lobe
/// this wide would look wrong, and rough surfaces are where rays cost most and show least).
constexpr float kTracedRoughness = 0.4f;
/// With sampled indirect light, only surfaces smoother than this trace the one mirror ray; the
/// rest sample their lobe (at this roughness the lobe is a degree or so wide).
constexpr float kSampledMirrorRoughness = 0.1f;
}  // namespace

Color WhittedTracer::missRadiance(const Vec3& d) const {
    return scene_.environment ? scene_.environment->radiance(d) : scene_.background;
}

Color WhittedTracer::primaryMiss(const Vec3& d) const {
    return scene_.environment && scene_.environmentBackground ? scene_.environment->radiance(d) : scene_.background;
}

Color WhittedTracer::traceReflection(const SurfaceInteraction& si, const Vec3& ng, const Vec3& dir, int depth,
                                     const Color& weight, RayStats& stats, uint64_t seed, float* tHit) const {
    const uint32_t skip = scene_.geometry.skipFor(si, dir);
    Ray rr;
    rr.o = spawnOrigin(si.p, si, ng, dir, skip);
    rr.d = dir;
    rr.coneWidth = si.coneWidth;
    rr.coneSpread = si.coneSpread;
    ++stats.reflection;
    return trace(rr, depth + 1, weight, stats, seed, skip, tHit);
}

Color WhittedTracer::shadeGltf(const SurfaceInteraction& si, const Vec3& d, int depth, const Color& weight,
                               RayStats& stats, uint64_t seed) const {
    const Vec3 V = -d;
    GltfSample g = gltfSample(scene_, si);
    const pbr::Surface& s = g.surface;
    if (g.unlit) return s.baseColor;  // KHR_materials_unlit: no light, no reflection
    const ShadingFrame frame = shadingFrame(scene_, si, V);
    // KHR_materials_iridescence: the film's terms at this view, once for all the lights and the
    // environment (only where there is a film).
    if (s.iridescence > 0.f) pbr::prepareFilm(g.surface, std::max(glm::dot(frame.ns, V), 1e-4f));
    const bool coated = s.clearcoat > 0.f;
    const bool sheen = s.sheenColor != Color(0.f);  // KHR_materials_sheen: over the base, under the coat
    Color c = g.emission;

    // Punctual lights through the BRDF, shadowed and pruned as the Phong model's are.
    ShadowRays shadows(scene_, si, frame, settings_.blockerCache ? &blockers_ : nullptr);
    float pruned = 0.f;
    const pbr::ViewTerms view = scene_.lights.empty() ? pbr::ViewTerms{} : pbr::viewTerms(s, frame.ns, V);
    for (const Light& L : scene_.lights) {
        LightIncidence li;
        if (!lightIncidence(L, si.p, frame.ns, li)) continue;
        const bool behindFacet = glm::dot(frame.ng, li.dir) <= 0.f;
        if (behindFacet && (si.mesh < 0 || !L.castShadows)) continue;
        const Color irradiance = li.att * L.intensity * L.color;
        Color term = pbr::directLight(s, frame.ns, V, li.dir, irradiance, view);
        if (sheen) term = pbr::sheenDirect(s, frame.ns, V, li.dir, term, irradiance);
        if (coated) term = pbr::clearcoatDirect(s, frame.nc, V, li.dir, term, irradiance);
        const float worth = maxComponent(weight * term) * displayScale_;
        if (pruned + worth <= settings_.minWeight) {
            pruned += worth;
            continue;
        }
        if (L.castShadows) {
            const Color t = shadows.transmittance(L, li, behindFacet, stats, seeThroughShadows_);
            if (t == Color(0.f)) continue;
            c += term * t;
        } else {
            c += term;
        }
    }

    // Indirect light: the environment (split sum) and, for smooth surfaces, the traced mirror ray.
    // With sampled indirect light (indirect_light.cpp) all but near-mirrors sample their lobe.
    const bool sampled = seed != kNoSampleSeed && depth < settings_.maxDepth;
    const float nv = std::max(glm::dot(frame.ns, V), 1e-4f);
    // The split sum's scale and bias, used twice below: looked up once, and only if needed (a
    // rough surface without an environment needs neither use).
    Vec2 scaleBias(0.f);
    bool haveScaleBias = false;
    auto splitSum = [&]() -> Vec2 {
        if (!haveScaleBias) scaleBias = pbr::specularScaleBias(nv, s.roughness), haveScaleBias = true;
        return scaleBias;
    };
    Vec3 R = reflect(d, frame.ns);
    if (glm::dot(R, frame.ng) <= 0.f) R = reflect(d, frame.ng);  // below the facet: mirror on ng
    Color specular(0.f);
    float traced = 0.f;
    // Glass reflects through the refraction path's exact Fresnel (traceHit); not twice here.
    if (s.transmission <= 0.f && depth < settings_.maxDepth) {
        const float share = sampled ? (s.roughness < kSampledMirrorRoughness ? 1.f : 0.f)
                                    : std::clamp(1.f - s.roughness / kTracedRoughness, 0.f, 1.f);
        const Color w = share > 0.f ? weight * share * s.occlusion * pbr::specularAlbedo(s, splitSum()) : Color(0.f);
        if (maxComponent(w) > settings_.minWeight) {
            specular = share * traceReflection(si, frame.ng, R, depth, w, stats, childSeed(seed, 3));
            traced = share;
        }
    }
    // Glass reflects the environment through the traced Fresnel ray already.
    const float glossy = (1.f - traced) * (1.f - s.transmission);
    IndirectRadiance ind;
    if (scene_.environment) {
        ind.specular = scene_.environment->specular(s.metallic > 0.f ? pbr::dominantDirection(frame.ns, R, s.roughness) : R,
                                                    s.roughness);
        ind.diffuse = scene_.environment->diffuse(frame.ns);
    }
    if (sampled) {
        const bool diffuse = (1.f - s.metallic) * (1.f - s.transmission) > 0.f;
        ind = sampleIndirect(si, frame, s, V, glossy, diffuse, ind, depth, weight, stats, seed);
    } else if (bounce_ && si.mesh >= 0) {
        // The lights' bounce off the scene's surfaces, cached per film (bounce_cache.h); the
        // environment's split sum above stays as it was, unshadowed.
        ind.diffuse += bounce_->at(scene_, si, frame.side);
    }
    specular += glossy * ind.specular;
    if (coated || sheen) {
        // The sheen gathers the light the diffuse lobe does (it is as wide, towards grazing) and
        // dims the base by its albedo; the coat reflects the environment around its own mirror
        // ray, at its own roughness, and lets through what its Fresnel leaves of the rest.
        Color base = pbr::environmentLight(s, splitSum(), specular, ind.diffuse);
        if (sheen) base = pbr::sheenEnvironment(s, nv, base, ind.diffuse);
        if (coated) {
            Vec3 Rc = reflect(d, frame.nc);
            if (glm::dot(Rc, frame.ng) <= 0.f) Rc = reflect(d, frame.ng);
            const float ncv = std::max(glm::dot(frame.nc, V), 1e-4f);
            Color coat = scene_.environment ? scene_.environment->specular(Rc, s.clearcoatRoughness) : Color(0.f);
            // A smooth coat traces its mirror ray, as a smooth base does, so it reflects the
            // scene and not only the environment; the same share rule fades it out by roughness.
            const float share = depth >= settings_.maxDepth ? 0.f
                                : sampled ? (s.clearcoatRoughness < kSampledMirrorRoughness ? 1.f : 0.f)
                                          : std::clamp(1.f - s.clearcoatRoughness / kTracedRoughness, 0.f, 1.f);
            if (share > 0.f) {
                const Vec2 ab = pbr::specularScaleBias(ncv, s.clearcoatRoughness);
                const Color w = weight * (share * s.occlusion * s.clearcoat * (0.04f * ab.x + ab.y));
                if (maxComponent(w) > settings_.minWeight)
                    coat = share * traceReflection(si, frame.ng, Rc, depth, w, stats, childSeed(seed, 4)) + (1.f - share) * coat;
            }
            base = pbr::clearcoatEnvironment(s, ncv, base, coat);
        }
        c += base;
    } else if (specular != Color(0.f) || ind.diffuse != Color(0.f)) {
        c += pbr::environmentLight(s, splitSum(), specular, ind.diffuse);
    }
    return c;
}

}  // namespace rf
