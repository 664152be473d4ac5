#pragma once
/// The shadow catcher of `--ground shadow`: an invisible horizontal plane under the model that
/// shows only the light the model takes from it, the product-shot look. Seen by camera rays
/// alone (nothing reflects it, nothing is shadowed by it), it dims what the ray would have seen
/// behind it (the background or the environment) by the share of the light the model blocks:
/// the key light's shadow and, from the environment, the contact darkening where the model
/// stands. Over a transparent background that share is the pixel's alpha.
#include <vector>

#include "engine/scene/scene.h"
#include "engine/util/stats.h"

namespace rf {

/// How much of the light arriving at a point of the catcher gets through.
struct CatcherLight {
    Color share{1.f};   ///< per channel: light arriving / light that would arrive without the model
    float shadow = 0.f; ///< 1 − the luminance share: the strength of the shadow (alpha), in [0, 1]
};

/// Puts the scene's ground: Shadow places the catcher at the bottom of the scene's bounds (a
/// note, and no ground, when nothing is bounded); None removes it.
void placeGround(Scene& scene, Ground ground);

class ShadowCatcher {
public:
    /// Over scene.ground (which must be set); the scene must outlive it.
    explicit ShadowCatcher(const Scene& scene);

    /// Distance along primary ray r to the catcher, if r meets it from above before tMax.
    bool hit(const Ray& r, float tMax, float& t) const;
    /// The light at catcher point p (on the plane; pError its rounding bound): every shadow-casting light through a shadow
    /// ray, and the environment (without one, the seed's ambient sky) through a fixed set of
    /// cosine-distributed directions, each weighted by the sky's radiance there. Exactly 1 where
    /// nothing blocks any of them, so an unshadowed catcher shows the background unchanged.
    CatcherLight light(const Vec3& p, const Vec3& pError, RayStats& stats) const;

    /// Directions sampled for the sky's share: enough that the contact shadow shows no steps.
    static constexpr int kSkyDirections = 64;

private:
    const Scene& scene_;
    float y_ = 0.f;
    Aabb reach_;  ///< beyond this box the model cannot darken the sky (nothing to test)
    std::vector<Vec3> dirs_;        ///< cosine-distributed about +Y
    std::vector<Color> skyWeight_;  ///< the sky's radiance along each, smoothed
    bool seeThrough_ = false;       ///< some material transmits: shadow rays filter through it
};

}  // namespace rf
