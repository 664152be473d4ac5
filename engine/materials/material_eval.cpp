#include "engine/materials/material_eval.h"

#include "engine/geometry/interaction.h"

namespace rf {

Vec4 baseColorTexel(const std::vector<Texture>& textures, const Material& m, Vec2 uv0, Vec2 uv1, Vec2 area) {
    if (m.baseColorTexture < 0) return Vec4(1.f);
    return sampleTexture(textures[m.baseColorTexture], textureUv(m.baseColorTransform, uv0, uv1),
                         textureFootprint(m.baseColorTransform, area));
}

namespace {
/// floor by truncation: baseline x86-64 has no roundsd, and libm's floor is a call.
long long floorToCell(double v) {
    if (!(std::abs(v) < 1e18)) return 0;  // beyond long long (or NaN): no meaningful cell
    const long long i = static_cast<long long>(v);
    return i - (static_cast<double>(i) > v);
}
}  // namespace

Color baseColor(const Material& m, const std::vector<Texture>& textures, const DVec3& renderOrigin,
                const SurfaceInteraction& si, float* alphaOut) {
    Color c = m.color;
    float alpha = m.alpha;
    if (m.checkerScale > 0.f) {
        // World coordinates in double: the render-space point plus the rebasing origin. The
        // small scale-relative bias keeps points lying exactly on a cell face (a floor at y = 0)
        // on one side, as POV-Ray's checker does.
        const DVec3 w = (DVec3(si.p) + renderOrigin) * (1.0 / double(m.checkerScale)) + DVec3(1e-4);
        const long long cell = floorToCell(w.x) + floorToCell(w.y) + floorToCell(w.z);
        c = (cell & 1) ? m.color2 : m.color;
    }
    if (m.baseColorTexture >= 0) {
        const Vec4 t = baseColorTexel(textures, m, si.uv, si.uv1, si.uvArea);
        c *= Color(t);
        alpha *= t.a;
    }
    c *= Color(si.color);  // COLOR_0 (white without one)
    alpha *= si.color.a;
    if (alphaOut) *alphaOut = alpha;
    return c;
}

Vec3 normalTextureSample(const std::vector<Texture>& textures, const Material& m, Vec2 uv0, Vec2 uv1, Vec2 area) {
    Vec3 tn = Vec3(sampleTexture(textures[m.normalTexture], textureUv(m.normalTransform, uv0, uv1),
                                 textureFootprint(m.normalTransform, area))) * 2.f - 1.f;
    tn.x *= m.normalScale;
    tn.y *= m.normalScale;
    return tn;
}

}  // namespace rf
