#include "light_eval.h"

#include "scene.h"

namespace rf {

namespace {
/// Hanika's shift: move the shadow-ray origin of a smooth-shaded triangle towards the surface its
/// vertex normals describe, so faces turned to the light are not shadowed by their own flat
/// neighbours. side = −1 when the surface is seen from behind: the vertex normals are flipped
/// with it, so the point moves towards the viewer's side, never through the surface.
Vec3 terminatorSafeOrigin(const Scene& scene, const SurfaceInteraction& si, float side) {
    if (si.mesh < 0) return si.p;
    const TriangleMesh& mesh = scene.meshes[si.mesh];
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

bool ShadowRays::unoccluded(const Light& L, const LightIncidence& li, bool behindFacet, RayStats& stats) {
    if (!shifted_) {
        base_ = terminatorSafeOrigin(scene_, si_, frame_.side);
        shifted_ = true;
    }
    const uint32_t skip = scene_.skipFor(si_, li.dir);
    Ray sr;
    sr.o = spawnOrigin(base_, si_, frame_.ng, behindFacet ? frame_.ng : li.dir, skip);
    sr.d = li.dir;
    // Shorten the far end relatively, so a light lying on a surface still lights it. An origin
    // still at si.p (no offset) already has its distance.
    const float tMax = std::isinf(li.dist) ? kInf
                                           : (sr.o == si_.p ? li.dist : glm::length(L.position - sr.o)) * (1.f - 1e-4f);
    ++stats.shadow;
    return !scene_.occluded(sr, tMax, skip);
}

}  // namespace rf
