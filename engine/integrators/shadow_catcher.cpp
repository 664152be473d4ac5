#include "engine/integrators/shadow_catcher.h"

#include "engine/materials/brdf_gltf.h"
#include "engine/scene/env_lighting.h"
#include "engine/lights/exposure.h"
#include "engine/integrators/light_eval.h"

namespace rf {

namespace {
/// The seed's default k_amb: without an environment, the sky is its ambient light at that share.
constexpr float kAmbientSky = 0.1f;
/// The model darkens the sky of points within this many of its largest extents around it; past
/// that its cosine-weighted share is below 1/500, less than one step of an 8-bit pixel.
constexpr float kSkyReach = 4.f;
}  // namespace

void placeGround(Scene& scene, Ground ground) {
    scene.shadowCatcherHeight.reset();
    if (ground == Ground::None) return;
    const Aabb b = scene.geometry.bounds();
    if (b.empty()) {
        scene.notes.push_back(scene.sourcePath + ": ground shadow: nothing bounded to stand on it; no ground");
        return;
    }
    scene.shadowCatcherHeight = b.lo.y;
}

ShadowCatcher::ShadowCatcher(const Scene& scene) : scene_(scene), y_(scene.shadowCatcherHeight.value_or(0.f)) {
    for (const Material& m : scene.materials) seeThrough_ |= m.gltfPbr && m.seesThrough();
    const Aabb b = scene.geometry.bounds();
    if (!b.empty()) {
        const Vec3 e = b.extent();
        const float grow = kSkyReach * std::max({e.x, e.y, e.z});
        reach_ = b;
        reach_.lo -= Vec3(grow);
        reach_.hi += Vec3(grow);
    }
    // Hammersley points through the cosine-weighted map: fixed, so the contact shadow is smooth
    // and the same in every frame and on every rank.
    for (uint32_t i = 0; i < kSkyDirections; ++i) {
        const Vec2 u = pbr::hammersley(i, kSkyDirections);
        const float r = std::sqrt(u.x), phi = 2.f * kPi * u.y;
        const Vec3 d(r * std::cos(phi), std::sqrt(std::max(0.f, 1.f - u.x)), r * std::sin(phi));
        dirs_.push_back(d);
        // The lobe-filtered radiance: a sharp light in the sky must not hang on one direction.
        skyWeight_.push_back(scene.environment ? scene.environment->specular(d, 0.6f) : scene.ambientLight * kAmbientSky);
    }
}

bool ShadowCatcher::hit(const Ray& r, float tMax, float& t) const {
    if (!(r.d.y < 0.f) || !(r.o.y > y_)) return false;  // seen from above only
    t = (y_ - r.o.y) / r.d.y;
    return t > 0.f && t < tMax;
}

CatcherLight ShadowCatcher::light(const Vec3& p, const Vec3& pError, RayStats& stats) const {
    SurfaceInteraction si;
    si.p = Vec3(p.x, y_, p.z);
    si.pError = pError;
    si.ng = si.ns = Vec3(0.f, 1.f, 0.f);
    const ShadingFrame frame{si.ng, si.ns, 1.f};
    ShadowRays shadows(scene_, si, frame);
    // Both sums run in the same order over the same terms, so with nothing in the way they are
    // equal to the bit and the share is exactly 1.
    Color full(0.f), seen(0.f);
    for (const Light& L : scene_.lights) {
        LightIncidence li;
        if (!lightIncidence(L, si.p, si.ns, li)) continue;
        const Color e = (li.att * L.intensity * li.cosine) * L.color;
        full += e;
        seen += L.castShadows ? e * shadows.transmittance(L, li, false, stats, seeThrough_) : e;
    }
    const bool near = si.p.x > reach_.lo.x && si.p.x < reach_.hi.x && si.p.z > reach_.lo.z && si.p.z < reach_.hi.z;
    Ray sky;
    sky.o = offsetRayOrigin(si.p, si.pError, si.ng, si.ng);
    const float perDirection = kPi / kSkyDirections;  // E = ∫L cos ≈ π/N · ΣL over cosine-distributed directions
    for (size_t i = 0; i < dirs_.size(); ++i) {
        const Color e = skyWeight_[i] * perDirection;
        full += e;
        if (near) {
            sky.d = dirs_[i];
            ++stats.shadow;
            if (scene_.geometry.occluded(sky, kInf)) continue;
        }
        seen += e;
    }
    CatcherLight out;
    for (int c = 0; c < 3; ++c) out.share[c] = full[c] > 0.f ? std::clamp(seen[c] / full[c], 0.f, 1.f) : 1.f;
    const float lf = luminance(full);
    out.shadow = lf > 0.f ? std::clamp(1.f - luminance(seen) / lf, 0.f, 1.f) : 0.f;
    return out;
}

}  // namespace rf
