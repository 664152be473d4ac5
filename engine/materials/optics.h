#pragma once
/// Reflection, Snell refraction and exact dielectric Fresnel.
#include "engine/util/vec_math.h"

namespace rf {

/// Mirror direction of incoming direction d about unit normal n.
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.f * glm::dot(d, n) * n; }

/// Refracts incoming direction d (unit) through unit normal n facing the incoming side;
/// eta = n_incident / n_transmitted. Returns false on total internal reflection.
inline bool refract(const Vec3& d, const Vec3& n, float eta, Vec3& out) {
    const float cosI = -glm::dot(n, d);
    const float sin2T = eta * eta * std::max(0.f, 1.f - cosI * cosI);
    if (sin2T >= 1.f) return false;
    const float cosT = std::sqrt(1.f - sin2T);
    out = glm::normalize(eta * d + (eta * cosI - cosT) * n);
    return true;
}

/// Exact Fresnel reflectance of an unpolarised wave at a dielectric boundary.
/// cosI: cosine of the incident angle (> 0 on the side the light comes from);
/// eta: n_transmitted / n_incident. Returns 1 under total internal reflection.
/// We use this, not Schlick's approximation, which strays by ~23% off its good range at n = 1.5.
inline float fresnelDielectric(float cosI, float eta) {
    cosI = std::clamp(cosI, -1.f, 1.f);
    if (cosI < 0.f) {
        eta = 1.f / eta;
        cosI = -cosI;
    }
    const float sin2I = 1.f - cosI * cosI;
    const float sin2T = sin2I / (eta * eta);
    if (sin2T >= 1.f) return 1.f;
    const float cosT = std::sqrt(std::max(0.f, 1.f - sin2T));
    const float rParl = (eta * cosI - cosT) / (eta * cosI + cosT);
    const float rPerp = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5f * (rParl * rParl + rPerp * rPerp);
}

/// KHR_materials_dispersion: the index at wavelength λ (nm) of a material of index n_d (at the
/// d line, 587.6 nm) and dispersion 20/V_d (V_d the Abbe number), by the specification's
/// two-term Cauchy fit: max(n_d + (n_d − 1)/V_d · (523655/λ² − 1.5168), 1).
inline float dispersedIor(float ior, float dispersion, double wavelengthNm) {
    const double abbeInverse = double(dispersion) / 20.0;
    return float(std::max(ior + (ior - 1.0) * abbeInverse * (523655.0 / (wavelengthNm * wavelengthNm) - 1.5168), 1.0));
}

/// Schlick's approximation, kept for comparison in tests only.
inline float fresnelSchlick(float cosI, float eta) {
    const float r0 = (eta - 1.f) / (eta + 1.f);
    const float m = 1.f - std::clamp(cosI, 0.f, 1.f);
    return r0 * r0 + (1.f - r0 * r0) * m * m * m * m * m;
}

}  // namespace rf
