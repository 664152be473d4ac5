#pragma once
/// Punctual lights with the seed's distance attenuation 1/(a + b·d + c·d²).
#include <string>

#include "engine/util/vec_math.h"

namespace rf {

enum class LightType { Point, Directional, Spot };

struct Light {
    std::string name;
    LightType type = LightType::Point;
    Vec3 position{0.f};
    Vec3 direction{0.f, -1.f, 0.f};  ///< unit; the way the light travels (directional, spot)
    Color color{1.f};
    float intensity = 1.f;
    Vec3 attenuation{1.f, 0.f, 0.f};  ///< (a, b, c); a = b = c = 0 is rejected at load time
    float innerCone = 0.f;            ///< spot: half angles in radians
    float outerCone = 0.7853982f;
    float range = 0.f;                ///< > 0: glTF-style smooth cut-off distance
    bool castShadows = true;
    /// glTF lights: intensity was given in cd (point, spot) or lx (directional) and divided by
    /// 683 lm/W; false for scene-file lights (unitless) and the built-in rig.
    bool photometric = false;
    /// A glTF light: the model (SceneGeometry::models) and node it hangs on, and its index in
    /// the file's KHR_lights_punctual lights, so the model's animations can move and change
    /// it; −1 for scene-file lights and the built-in rig.
    int model = -1, node = -1, source = -1;
};

/// 1/(a + b·d + c·d²); finite for any d ≥ 0 when the coefficients are valid.
inline float attenuationFactor(const Vec3& abc, float d) {
    // Constant attenuation (the default a = 1): no division in double per shading point.
    if (abc.y == 0.f && abc.z == 0.f) return abc.x > 0.f ? 1.f / abc.x : 0.f;
    const double den = double(abc.x) + double(abc.y) * d + double(abc.z) * double(d) * d;
    if (!(den > 0.0)) return 0.f;
    const double f = 1.0 / den;
    return std::isfinite(f) ? static_cast<float>(f) : 0.f;
}

/// Smooth falloff between the outer and inner cone (cosine domain).
inline float spotFactor(const Light& l, const Vec3& toPoint) {
    const float cosOuter = std::cos(l.outerCone), cosInner = std::cos(l.innerCone);
    const float c = glm::dot(glm::normalize(l.direction), toPoint);
    if (c <= cosOuter) return 0.f;
    if (c >= cosInner || cosInner <= cosOuter) return 1.f;
    const float x = (c - cosOuter) / (cosInner - cosOuter);
    return x * x;
}

}  // namespace rf
