#pragma once
/// Light evaluation at a surface point, apart from any material model: where a punctual light
/// comes from, how much of it arrives (distance attenuation, range window, spot cone), and
/// whether a shadow ray reaches it.
#include <vector>

#include "engine/lights/light.h"
#include "engine/geometry/ray.h"
#include "engine/integrators/shading_frame.h"
#include "engine/util/stats.h"

namespace rf {

class Scene;
struct SurfaceInteraction;

/// Where a light comes from at a point and how much of it arrives there, before shadowing.
struct LightIncidence {
    Vec3 dir{0.f};       ///< unit, from the point towards the light
    float dist = kInf;   ///< to the light; infinite for a directional light
    float att = 1.f;     ///< 1/(a + b·d + c·d²) × range window × spot cone
    float cosine = 0.f;  ///< n·dir with the shading normal
};

/// Fills li for light L at point p with shading normal ns. False when L cannot light that side:
/// behind the normal, at the point itself, or attenuated to nothing. The early outs read squared
/// and unnormalised values, so none of them waits for the square root and the division.
inline bool lightIncidence(const Light& L, const Vec3& p, const Vec3& ns, LightIncidence& li) {
    if (L.type == LightType::Directional) {
        li.dir = -L.direction;
        li.dist = kInf;
        li.att = 1.f;
        li.cosine = glm::dot(ns, li.dir);
    } else {
        const Vec3 toL = L.position - p;
        const float dist2 = glm::dot(toL, toL);
        const float nlRaw = glm::dot(ns, toL);
        if (!(dist2 > 0.f) || nlRaw <= 0.f) return false;
        li.dist = std::sqrt(dist2);
        const float invDist = 1.f / li.dist;
        li.dir = toL * invDist;
        li.cosine = nlRaw * invDist;
        li.att = attenuationFactor(L.attenuation, li.dist);
        if (L.range > 0.f) {
            const float r = li.dist / L.range;
            const float w = std::clamp(1.f - r * r * r * r, 0.f, 1.f);
            li.att *= w * w;
        }
        if (L.type == LightType::Spot) li.att *= spotFactor(L, -li.dir);
    }
    return li.cosine > 0.f && li.att > 0.f;
}

/// Where a ray leaving si starts. One that skips si's own primitive (the plane, or the sphere it
/// leaves outwards: SceneGeometry::skipFor) cannot re-meet it however p rounded, so it starts at p and
/// saves the offset; any other is pushed off the surface by p's error bound along ng, on the
/// side `side` points to.
Vec3 spawnOrigin(const Vec3& p, const SurfaceInteraction& si, const Vec3& ng, const Vec3& side, uint32_t skip);

/// Per light, the triangle that last blocked its shadow ray (SceneGeometry::occluded's lastBlocker), for
/// the next shading point of the same thread; SceneGeometry::kNoPrim before any. Only what the shadow
/// queries cost depends on it, never what they answer, so results stay those of any thread count.
struct ShadowBlockers {
    explicit ShadowBlockers(size_t lights = 0) : prim(lights, ~0u) {}
    std::vector<uint32_t> prim;
};

/// The shadow rays of one shading point. The origin of a smooth-shaded triangle is shifted once
/// (Hanika 2021, "Hacking the shadow terminator"), for the first light that needs a ray.
class ShadowRays {
public:
    /// blockers (may be null): the calling thread's, sized to scene.lights.
    ShadowRays(const Scene& scene, const SurfaceInteraction& si, const ShadingFrame& frame, ShadowBlockers* blockers = nullptr)
        : scene_(scene), si_(si), frame_(frame), blockers_(blockers) {}

    /// True when nothing blocks the way from the point to light L (counted as a shadow ray).
    /// behindFacet: L lies behind the flat facet though in front of the smooth surface; the ray
    /// then leaves on the viewer's side of the facet and must clear the facet's neighbours.
    bool unoccluded(const Light& L, const LightIncidence& li, bool behindFacet, RayStats& stats);
    /// What reaches the point from light L: 1 unblocked, 0 blocked, and through glTF materials
    /// with KHR_materials_transmission their colour × transmission × (1 − Fresnel) per surface
    /// crossed (no bending: a Whitted shadow ray goes straight), so glass casts a light shadow;
    /// inside a KHR_materials_volume, Beer–Lambert over the straight way through it as well.
    /// seeThrough false: the plain unoccluded() test.
    Color transmittance(const Light& L, const LightIncidence& li, bool behindFacet, RayStats& stats, bool seeThrough);

private:
    /// The shadow ray towards L and its length.
    Ray shadowRay(const Light& L, const LightIncidence& li, bool behindFacet, uint32_t& skip, float& tMax);

    const Scene& scene_;
    const SurfaceInteraction& si_;
    const ShadingFrame& frame_;
    ShadowBlockers* blockers_;
    bool shifted_ = false;
    Vec3 base_{0.f};
};

}  // namespace rf
