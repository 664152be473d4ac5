#include "engine/integrators/shading_frame.h"

#include "engine/materials/material_eval.h"
#include "engine/scene/scene.h"

namespace rf {

namespace {
/// ns bent by the normal texture in the frame of the interpolated tangent (Gram–Schmidt against
/// ns, handedness in tangent.w); ns unchanged where that frame or the result degenerates.
Vec3 normalMapped(const SurfaceInteraction& si, const Vec3& ns, const Vec3& tn) {
    Vec3 t = Vec3(si.tangent) - ns * glm::dot(ns, Vec3(si.tangent));
    const float tl = glm::length(t);
    if (!(tl > 0.f)) return ns;
    t /= tl;
    const Vec3 b = glm::cross(ns, t) * (si.tangent.w < 0.f ? -1.f : 1.f);
    const Vec3 n = t * tn.x + b * tn.y + ns * tn.z;
    const float nl = glm::length(n);
    return (nl > 0.f && std::isfinite(nl)) ? n / nl : ns;
}
}  // namespace

ShadingFrame shadingFrame(const Scene& scene, const SurfaceInteraction& si, const Vec3& V) {
    const Material& m = scene.materials[si.material];
    ShadingFrame f{si.ng, si.ns, 1.f};
    if (glm::dot(f.ng, V) < 0.f) {
        f.ng = -f.ng;
        f.ns = -f.ns;
        f.side = -1.f;
    }
    const Vec3 interpolated = f.ns;
    if (m.normalTexture >= 0 && si.tangent != Vec4(0.f))
        f.ns = normalMapped(si, f.ns, normalTextureSample(scene.textures, m, si.uv, si.uv1, si.uvArea));
    if (glm::dot(f.ns, V) <= 0.f) f.ns = f.ng;
    f.nc = f.ns;
    if (m.clearcoat > 0.f) {
        f.nc = interpolated;
        if (m.clearcoatNormalTexture >= 0 && si.tangent != Vec4(0.f)) {
            const TextureTransform& t = m.clearcoatNormalTransform;
            Vec3 tn = Vec3(sampleTexture(scene.textures[size_t(m.clearcoatNormalTexture)], textureUv(t, si.uv, si.uv1),
                                         textureFootprint(t, si.uvArea))) * 2.f - 1.f;
            tn.x *= m.clearcoatNormalScale;
            tn.y *= m.clearcoatNormalScale;
            f.nc = normalMapped(si, interpolated, tn);
        }
        if (glm::dot(f.nc, V) <= 0.f) f.nc = f.ng;
    }
    return f;
}

}  // namespace rf
