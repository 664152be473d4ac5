#include "engine/materials/specular_glossiness.h"

namespace rf {

namespace {

constexpr float kDielectricF0 = 0.04f;

float perceivedBrightness(const Color& c) { return std::sqrt(0.299f * c.r * c.r + 0.587f * c.g * c.g + 0.114f * c.b * c.b); }

/// The metallic that gives a dielectric f0 of 0.04 and the diffuse and specular brightnesses
/// seen: the root of a·m² + b·m + c = 0.
float solveMetallic(float diffuse, float specular, float oneMinusSpecularStrength) {
    if (specular < kDielectricF0) return 0.f;
    const float a = kDielectricF0,
                b = diffuse * oneMinusSpecularStrength / (1.f - kDielectricF0) + specular - 2.f * kDielectricF0,
                c = kDielectricF0 - specular;
    const float d = std::max(b * b - 4.f * a * c, 0.f);
    return std::clamp((-b + std::sqrt(d)) / (2.f * a), 0.f, 1.f);
}

}  // namespace

SpecularGlossinessAsMetallic convertSpecularGlossiness(const Color& d, const Color& s, float glossiness) {
    SpecularGlossinessAsMetallic out;
    const float maxSpecular = std::max({s.r, s.g, s.b});
    out.metallic = solveMetallic(perceivedBrightness(d), perceivedBrightness(s), 1.f - maxSpecular);
    const Color fromDiffuse = d * ((1.f - maxSpecular) / (1.f - kDielectricF0) / std::max(1.f - out.metallic, 1e-4f));
    const Color fromSpecular = (s - Color(kDielectricF0 * (1.f - out.metallic))) / std::max(out.metallic, 1e-4f);
    out.baseColor = glm::clamp(glm::mix(fromDiffuse, fromSpecular, out.metallic * out.metallic), Color(0.f), Color(1.f));
    out.roughness = std::clamp(1.f - glossiness, 0.f, 1.f);
    return out;
}

}  // namespace rf
