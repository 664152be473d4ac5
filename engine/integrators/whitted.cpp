#include "engine/integrators/whitted.h"

#include <new>

#include "engine/scene/env_lighting.h"
#include "engine/scene/scene_cache.h"
#include "engine/util/image.h"
#include "engine/integrators/light_eval.h"
#include "engine/materials/material_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/materials/optics.h"
#include "engine/materials/thin_film.h"
#include "engine/util/sampler.h"
#include "engine/integrators/shading_frame.h"

namespace rf {

WhittedTracer::WhittedTracer(const Scene& scene, const RenderSettings& settings, SceneCacheSlot* bounceSlot)
    : scene_(scene), settings_(settings), blockers_(scene.lights.size()) {
    specFloor_.reserve(scene.materials.size());
    for (const Material& m : scene.materials)
        specFloor_.push_back(m.shininess > 0.f ? std::exp2(-40.f / m.shininess) : 0.f);
    displayScale_ = exposureScale(settings.exposure);
    for (const Material& m : scene.materials) seeThroughShadows_ |= m.gltfPbr && m.seesThrough();
    for (const Material& m : scene.materials) blending_ |= m.gltfPbr && m.alphaMode == AlphaMode::Blend;
    if (scene.shadowCatcherHeight) catcher_.emplace(scene);
    // renderRect built it on all its threads already; a tracer made alone builds its own.
    SceneCacheSlot own;
    bounce_ = bounceCache(scene, settings, bounceSlot ? bounceSlot : &own, 1);
}

std::unique_ptr<Integrator> makeIntegrator(const Scene& scene, const RenderSettings& settings,
                                           SceneCacheSlot* bounceSlot) {
    switch (settings.integrator) {
        case IntegratorKind::Whitted: break;
    }
    return std::make_unique<WhittedTracer>(scene, settings, bounceSlot);
}

float WhittedTracer::specular(const Material& m, int material, const Vec3& ns, const Vec3& l, const Vec3& V) const {
    const float x = settings_.shading == ShadingModel::BlinnPhong ? glm::dot(ns, glm::normalize(l + V))
                                                                  : glm::dot(reflect(-l, ns), V);
    // x^n below 2^-40 cannot show: skip pow (and its slow underflow path) there.
    return x > specFloor_[material] ? m.specular * std::pow(x, m.shininess) : 0.f;
}

Color WhittedTracer::shade(const SurfaceInteraction& si, const Vec3& d, RayStats& stats, const Color& weight) const {
    const Material& m = scene_.materials[si.material];
    const Vec3 V = -d;
    const Color base = baseColor(scene_, si);
    const ShadingFrame frame = shadingFrame(scene_, si, V);

    Color c = m.emission + scene_.ambientLight * m.ambient * base;
    if (m.diffuse <= 0.f && m.specular <= 0.f) return c;
    ShadowRays shadows(scene_, si, frame, settings_.blockerCache ? &blockers_ : nullptr);
    float pruned = 0.f;  // worth of the lights left out so far
    for (const Light& L : scene_.lights) {
        LightIncidence li;
        if (!lightIncidence(L, si.p, frame.ns, li)) continue;
        // The light is behind the flat facet but in front of the smooth (interpolated) surface:
        // Hanika's shadow-terminator case. Lit only if a shadow ray from the shifted point,
        // leaving on the viewer's side of the facet, clears the facet and its neighbours.
        const bool behindFacet = glm::dot(frame.ng, li.dir) <= 0.f;
        if (behindFacet && (si.mesh < 0 || !L.castShadows)) continue;
        const float spec = m.specular > 0.f ? specular(m, si.material, frame.ns, li.dir, V) : 0.f;
        const Color term = li.att * L.intensity * L.color * (m.diffuse * li.cosine * base + Color(spec));
        // The seed's pruning rule applied to the shadow ray: a light whose whole unshadowed term
        // would reach the pixel below the weight threshold is left out with its ray, as long as
        // all lights left out at this point stay below it together (many dim lights add up).
        const float worth = maxComponent(weight * term) * displayScale_;
        if (pruned + worth <= settings_.minWeight) {
            pruned += worth;
            continue;
        }
        if (!L.castShadows) {
            c += term;
            continue;
        }
        const Color t = shadows.transmittance(L, li, behindFacet, stats, seeThroughShadows_);
        if (t != Color(0.f)) c += term * t;
    }
    return c;
}

Color WhittedTracer::Li(const Ray& r, uint64_t seed, RayStats& stats, float* coverage) const {
    Hit h;
    const bool met = scene_.geometry.intersect(r, h);
    return primaryLi(r, met, h, seed, stats, coverage);
}

void WhittedTracer::LiPacket(const Ray* rays, int n, uint64_t wanted, const uint64_t* seeds, RayStats& stats, Color* out,
                             float* coverage) const {
    if (n > Bvh::kPacketMax) return Integrator::LiPacket(rays, n, wanted, seeds, stats, out, coverage);
    // Only the packet's own hits are made: 64 default Hits would cost more than a small packet.
    alignas(Hit) unsigned char storage[sizeof(Hit) * Bvh::kPacketMax];
    Hit* hits = reinterpret_cast<Hit*>(storage);
    for (int i = 0; i < n; ++i) new (hits + i) Hit();
    bool met[Bvh::kPacketMax];
    scene_.geometry.intersectPacket(rays, n, hits, met);
    // Misses that show the environment are looked up four at a time, the rest ray by ray.
    const bool envBackground = scene_.environment && scene_.environmentBackground && !scene_.primaryMissesEmpty();
    int misses[Bvh::kPacketMax], nMiss = 0;
    for (int i = 0; i < n; ++i) {
        if (!((wanted >> i) & 1u)) continue;
        float tGround = 0.f;
        if (envBackground && !met[i] && !(catcher_ && catcher_->hit(rays[i], kInf, tGround))) {
            ++stats.primary;
            if (coverage) coverage[i] = 0.f;
            misses[nMiss++] = i;
            continue;
        }
        out[i] = primaryLi(rays[i], met[i], hits[i], seeds[i], stats, coverage ? coverage + i : nullptr);
    }
    for (int k = 0; k < nMiss; k += 4) {
        Vec3 d[4];
        Color c[4];
        for (int j = 0; j < 4; ++j) d[j] = rays[misses[std::min(k + j, nMiss - 1)]].d;
        scene_.environment->radiance4(d, c);
        for (int j = 0; j < 4 && k + j < nMiss; ++j) out[misses[k + j]] = c[j];
    }
}

Color WhittedTracer::primaryLi(const Ray& r, bool met, const Hit& h, uint64_t seed, RayStats& stats, float* coverage) const {
    ++stats.primary;
    if (settings_.indirectSamples <= 0) seed = kNoSampleSeed;
    float tGround = 0.f;
    if (catcher_ && catcher_->hit(r, met ? h.t : kInf, tGround)) return groundLi(r, tGround, stats, coverage);
    if (coverage) *coverage = met ? 1.f : 0.f;
    if (!met) return scene_.primaryMissesEmpty() ? Color(0.f) : primaryMiss(r.d);
    return traceHit(r, h, 1, Color(1.f), stats, seed, coverage);
}

Color WhittedTracer::groundLi(const Ray& r, float t, RayStats& stats, float* coverage) const {
    // p = o + t·d to a few ulps of each term (pbrt's bound for a point on a ray).
    const Vec3 p = r.o + t * r.d;
    const Vec3 pError = gamma(5) * (absComponents(r.o) + absComponents(t * r.d));
    const CatcherLight l = catcher_->light(p, pError, stats);
    if (scene_.primaryMissesEmpty()) {
        if (coverage) *coverage = l.shadow;
        return Color(0.f);
    }
    if (coverage) *coverage = 1.f;
    return primaryMiss(r.d) * l.share;
}

Color WhittedTracer::trace(const Ray& r, int depth, const Color& weight, RayStats& stats, uint64_t seed, uint32_t skip,
                           float* tHit) const {
    Hit hit;
    if (!scene_.geometry.intersect(r, hit, skip)) {
        if (tHit) *tHit = kInf;
        return depth == 1 ? primaryMiss(r.d) : missRadiance(r.d);
    }
    if (tHit) *tHit = hit.t;
    return traceHit(r, hit, depth, weight, stats, seed);
}

Color WhittedTracer::volumeTransmittance(const SurfaceInteraction& si, float t) const {
    const Material& m = scene_.materials[si.material];
    if (!m.volume() || m.attenuation == Color(0.f)) return Color(1.f);
    const float thickness = gltfThickness(scene_, si);
    if (!(thickness > 0.f)) return Color(1.f);  // thin-walled here (the thickness texture's 0)
    const float d = std::isinf(t) ? thickness : t;
    return glm::exp(-m.attenuation * d);
}

Color WhittedTracer::traceHit(const Ray& r, const Hit& hit, int depth, const Color& weight, RayStats& stats,
                              uint64_t seed, float* coverage) const {
    if (coverage) *coverage = 1.f;
    if (!blending_) return surfaceHit(r, scene_.geometry.interaction(r, hit), depth, weight, stats, seed);
    // alphaMode BLEND: each blended surface along the ray's straight way adds its covered share
    // (gltfCoverage) and lets the rest on to what lies behind, unbent and untinted, until a
    // surface covers all, the ray leaves, or what is left would not show. Passing costs no
    // depth, so a stack of cut-outs (leaves) shows whole; it is bounded by what the line meets.
    Ray ray = r;
    Hit h = hit;
    Color c(0.f);
    float pass = 1.f;  // the share of the ray not covered yet
    for (int crossing = 0;; ++crossing) {
        const SurfaceInteraction si = scene_.geometry.interaction(ray, h);
        const float cover = crossing < kBlendCrossings ? gltfCoverage(scene_, si) : 1.f;
        const uint64_t s = crossing == 0 ? seed : childSeed(seed, 16 + uint64_t(crossing));
        if (cover > 0.f) c += (pass * cover) * surfaceHit(ray, si, depth, weight * (pass * cover), stats, s);
        pass *= 1.f - cover;
        if (!(pass > 0.f) || maxComponent(weight) * pass <= settings_.minWeight) {
            if (coverage) *coverage = 1.f - pass;
            return c;
        }
        const uint32_t skip = scene_.geometry.skipFor(si, ray.d);
        ray.o = spawnOrigin(si.p, si, si.ng, ray.d, skip);
        ray.coneWidth = si.coneWidth;
        ray.coneSpread = si.coneSpread;
        ++stats.refraction;
        h = Hit();
        if (!scene_.geometry.intersect(ray, h, skip)) {
            if (coverage) *coverage = 1.f - pass;
            const Color behind = depth > 1 ? missRadiance(ray.d) : scene_.primaryMissesEmpty() ? Color(0.f) : primaryMiss(ray.d);
            return c + pass * behind;
        }
    }
}

Color WhittedTracer::surfaceHit(const Ray& r, const SurfaceInteraction& si, int depth, const Color& weight, RayStats& stats,
                                uint64_t seed) const {
    const bool gltf = scene_.materials[si.material].gltfPbr;
    Color c = gltf ? shadeGltf(si, r.d, depth, weight, stats, childSeed(seed, 0)) : shade(si, r.d, stats, weight);
    if (depth >= settings_.maxDepth) return c;

    const Material& m = scene_.materials[si.material];
    float kr = m.reflection;
    float kt = 0.f;
    Vec3 ng = si.ng;
    const bool entering = glm::dot(r.d, ng) < 0.f;
    if (!entering) ng = -ng;  // ng now faces the incoming ray
    // The shading normal, on the side of the facet that faces the ray. Reflection, refraction
    // and Fresnel follow it, so glass through a smooth mesh bends as the smooth surface would;
    // where it disagrees with the facet (seen from behind, or a direction that would not leave
    // or cross the facet), the geometric normal decides instead.
    Vec3 ns = si.ns;
    if (glm::dot(ns, ng) < 0.f) ns = -ns;
    if (!(glm::dot(r.d, ns) < 0.f)) ns = ng;
    Vec3 refrDir(0.f);
    // glTF: the metal part does not transmit (gltfTransmission).
    const float transmission = gltf && m.transmission > 0.f ? gltfTransmission(scene_, si) : m.transmission;
    if (gltf && m.dispersion > 0.f && transmission > 0.f)
        return c + dispersiveRays(r, si, depth, weight, stats, seed, transmission, entering, ng, ns);
    if (transmission > 0.f) {
        const float etaI = entering ? 1.f : m.ior, etaT = entering ? m.ior : 1.f;
        float F = fresnelDielectric(-glm::dot(r.d, ns), etaT / etaI);
        bool through = F < 1.f && refract(r.d, ns, etaI / etaT, refrDir);
        if (through && glm::dot(refrDir, ng) >= 0.f) {  // would not cross the facet: refract on ng
            F = fresnelDielectric(-glm::dot(r.d, ng), etaT / etaI);
            through = F < 1.f && refract(r.d, ng, etaI / etaT, refrDir);
        }
        kr += transmission * F;
        if (through) kt = transmission * (1.f - F);
    }
    if (kr > 0.f) {
        const Color w = weight * kr;
        if (maxComponent(w) > settings_.minWeight) {
            Vec3 dir = reflect(r.d, ns);
            if (glm::dot(dir, ng) <= 0.f) dir = reflect(r.d, ng);  // below the surface: use ng
            float t = kInf;
            const Color back = traceReflection(si, ng, dir, depth, w, stats, childSeed(seed, 1), &t);
            // Reflected inside a volume (leaving it, or totally reflected): the way back crosses it.
            c += kr * (entering ? back : back * volumeTransmittance(si, t));
        }
    }
    if (kt > 0.f) {
        const Color filter = baseColor(scene_, si);
        const Color w = weight * kt * filter;
        if (maxComponent(w) > settings_.minWeight) {
            const uint32_t skip = scene_.geometry.skipFor(si, refrDir);
            Ray tr;
            tr.o = spawnOrigin(si.p, si, ng, refrDir, skip);
            tr.d = refrDir;
            tr.coneWidth = si.coneWidth;
            tr.coneSpread = si.coneSpread;
            ++stats.refraction;
            float t = kInf;
            const Color through = trace(tr, depth + 1, w, stats, childSeed(seed, 2), skip, &t);
            // Refracted into a volume: Beer–Lambert over the way to the next surface.
            c += kt * filter * (entering ? through * volumeTransmittance(si, t) : through);
        }
    }
    return c;
}

Color WhittedTracer::dispersiveRays(const Ray& r, const SurfaceInteraction& si, int depth, const Color& weight, RayStats& stats,
                                    uint64_t seed, float transmission, bool entering, const Vec3& ng, const Vec3& ns) const {
    const Material& m = scene_.materials[si.material];
    int only = -1, carried = 0;
    for (int k = 0; k < 3; ++k)
        if (weight[k] != 0.f) only = k, ++carried;
    const int first = carried == 1 ? only : 0, last = carried == 1 ? only : 2;
    const Color filter = baseColor(scene_, si);
    Color c(0.f), kr(0.f);
    for (int k = first; k <= last; ++k) {
        // The channel's index at its wavelength (the ones the thin film uses, thin_film.h).
        const float ior = dispersedIor(m.ior, m.dispersion, pbr::kFilmWavelengthsNm[k]);
        const float etaI = entering ? 1.f : ior, etaT = entering ? ior : 1.f;
        Vec3 refrDir(0.f);
        float F = fresnelDielectric(-glm::dot(r.d, ns), etaT / etaI);
        bool through = F < 1.f && refract(r.d, ns, etaI / etaT, refrDir);
        if (through && glm::dot(refrDir, ng) >= 0.f) {
            F = fresnelDielectric(-glm::dot(r.d, ng), etaT / etaI);
            through = F < 1.f && refract(r.d, ng, etaI / etaT, refrDir);
        }
        kr[k] = transmission * F;
        if (!through) continue;
        const float kt = transmission * (1.f - F);
        Color mask(0.f);
        mask[k] = 1.f;
        const Color w = weight * kt * filter * mask;
        if (!(maxComponent(w) > settings_.minWeight)) continue;
        const uint32_t skip = scene_.geometry.skipFor(si, refrDir);
        Ray tr;
        tr.o = spawnOrigin(si.p, si, ng, refrDir, skip);
        tr.d = refrDir;
        tr.coneWidth = si.coneWidth;
        tr.coneSpread = si.coneSpread;
        ++stats.refraction;
        float t = kInf;
        // Streams of their own: 16 + crossing (up to kBlendCrossings) are the blended crossings'.
        const Color passed = trace(tr, depth + 1, w, stats, childSeed(seed, 1024 + uint64_t(k)), skip, &t);
        c += kt * filter * mask * (entering ? passed * volumeTransmittance(si, t) : passed);
    }
    const Color w = weight * kr;
    if (maxComponent(w) > settings_.minWeight) {
        Vec3 dir = reflect(r.d, ns);
        if (glm::dot(dir, ng) <= 0.f) dir = reflect(r.d, ng);
        float t = kInf;
        const Color back = traceReflection(si, ng, dir, depth, w, stats, childSeed(seed, 1), &t);
        c += kr * (entering ? back : back * volumeTransmittance(si, t));
    }
    return c;
}

}  // namespace rf
