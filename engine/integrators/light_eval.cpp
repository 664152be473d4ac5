#include "engine/integrators/light_eval.h"

#include <functional>

#include "engine/materials/material_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/materials/optics.h"
#include "engine/scene/scene.h"

namespace rf {

namespace {
/// Hanika's shift: move the shadow-ray origin of a smooth-shaded triangle towards the surface its
/// vertex normals describe, so faces turned to the light are not shadowed by their own flat
/// neighbours. side = −1 when the surface is seen from behind: the vertex normals are flipped
/// with it, so the point moves towards the viewer's side, never through the surface.
Vec3 terminatorSafeOrigin(const Scene& scene, const SurfaceInteraction& si, float side) {
    if (si.mesh < 0) return si.p;
    const TriangleMesh& mesh = scene.geometry.meshes[si.mesh];
    if (mesh.normals.empty()) return si.p;
    const uint32_t* idx = &mesh.indices[3 * si.tri];
    const float b[3] = {si.bary.b0, si.bary.b1, si.bary.b2};
    Vec3 shifted = si.p;
    for (int k = 0; k < 3; ++k) {
        const Vec3& v = mesh.positions[idx[k]];
        const Vec3 n = side * mesh.normals[idx[k]];
        Vec3 tmp = si.p - v;
        const float dn = std::min(0.f, glm::dot(tmp, n));
        tmp -= dn * n;
        shifted += b[k] * (tmp - (si.p - v));
    }
    // Vertex normals that disagree with the facet (turned away from it) would push the point
    // through the surface; Hanika's shift only ever lifts it to the viewer's side.
    if (!isFinite(shifted) || glm::dot(shifted - si.p, side * si.ng) < 0.f) return si.p;
    return shifted;
}
}  // namespace

Vec3 spawnOrigin(const Vec3& p, const SurfaceInteraction& si, const Vec3& ng, const Vec3& side, uint32_t skip) {
    return skip == si.prim ? p : offsetRayOrigin(p, si.pError, ng, side);
}

Ray ShadowRays::shadowRay(const Light& L, const LightIncidence& li, bool behindFacet, uint32_t& skip, float& tMax) {
    if (!shifted_) {
        base_ = terminatorSafeOrigin(scene_, si_, frame_.side);
        shifted_ = true;
    }
    skip = scene_.geometry.skipFor(si_, li.dir);
    Ray sr;
    sr.o = spawnOrigin(base_, si_, frame_.ng, behindFacet ? frame_.ng : li.dir, skip);
    sr.d = li.dir;
    // Shorten the far end relatively, so a light lying on a surface still lights it. An origin
    // still at si.p (no offset) already has its distance.
    tMax = std::isinf(li.dist) ? kInf : (sr.o == si_.p ? li.dist : glm::length(L.position - sr.o)) * (1.f - 1e-4f);
    return sr;
}

bool ShadowRays::unoccluded(const Light& L, const LightIncidence& li, bool behindFacet, RayStats& stats) {
    uint32_t skip = 0;
    float tMax = 0.f;
    const Ray sr = shadowRay(L, li, behindFacet, skip, tMax);
    ++stats.shadow;
    uint32_t* last = nullptr;
    // L's index if it is one of the scene's lights (std::less orders any two pointers; only
    // then is the subtraction defined); any other light goes uncached.
    const Light* lights = scene_.lights.data();
    const std::less<const Light*> before;
    if (blockers_ && !before(&L, lights) && before(&L, lights + blockers_->prim.size()))
        last = &blockers_->prim[size_t(&L - lights)];
    return !scene_.geometry.occluded(sr, tMax, skip, last);
}

Color ShadowRays::transmittance(const Light& L, const LightIncidence& li, bool behindFacet, RayStats& stats, bool seeThrough) {
    if (!seeThrough) return unoccluded(L, li, behindFacet, stats) ? Color(1.f) : Color(0.f);
    uint32_t skip = 0;
    float tMax = 0.f;
    Ray sr = shadowRay(L, li, behindFacet, skip, tMax);
    Color t(1.f);
    // A few glass surfaces at most (a sphere is two); beyond that the light is taken as blocked.
    for (int crossing = 0; crossing < 8; ++crossing) {
        ++stats.shadow;
        sr.tMax = tMax;
        Hit hit;
        if (!scene_.geometry.intersect(sr, hit, skip)) return t;
        const SurfaceInteraction hs = scene_.geometry.interaction(sr, hit);
        const Material& m = scene_.materials[hs.material];
        if (!m.gltfPbr || !m.seesThrough()) return Color(0.f);  // opaque
        // Fresnel at the smooth surface the shading normal describes (as refraction uses it),
        // the facet's where the two disagree about which side the ray comes from.
        const bool entering = glm::dot(sr.d, hs.ng) < 0.f;
        const float cosNs = glm::dot(sr.d, hs.ns);
        const float cosI = (cosNs < 0.f) == entering && cosNs != 0.f ? std::abs(cosNs) : std::abs(glm::dot(sr.d, hs.ng));
        const float F = m.transmission > 0.f ? fresnelDielectric(cosI, entering ? m.ior : 1.f / m.ior) : 0.f;
        // Metal transmits nothing; a blended surface passes its uncovered share untinted.
        t *= gltfPassing(scene_, hs, F);
        // Leaving a volume (KHR_materials_volume): Beer–Lambert over the way inside, from the
        // surface the ray entered by (or the shading point, inside) to here.
        if (!entering && m.volume() && m.attenuation != Color(0.f) && gltfThickness(scene_, hs) > 0.f)
            t *= glm::exp(-m.attenuation * hit.t);
        if (maxComponent(t) < 1e-4f) return Color(0.f);
        skip = scene_.geometry.skipFor(hs, sr.d);
        const Vec3 o = spawnOrigin(hs.p, hs, hs.ng, sr.d, skip);
        if (!std::isinf(tMax)) tMax = std::max(0.f, tMax - glm::length(o - sr.o));
        sr.o = o;
    }
    return Color(0.f);
}

}  // namespace rf
