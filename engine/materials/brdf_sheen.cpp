#include "engine/materials/brdf_sheen.h"

#include <array>
#include <mutex>

#include "engine/materials/brdf_gltf.h"

namespace rf::pbr {

float sheenAlpha(float roughness) {
    const float r = std::clamp(std::isfinite(roughness) ? roughness : 1.f, kMinSheenRoughness, 1.f);
    return r * r;
}

float charlieD(float nh, float alpha) {
    const float invA = 1.f / alpha;
    const float sin2 = std::max(0.f, (1.f - nh) * (1.f + nh));
    return (2.f + invA) * std::pow(sin2, 0.5f * invA) / (2.f * kPi);
}

namespace {

/// The extension's fit of the sheen's shadowing exponent: l(x) = a/(1 + b·x^c) + d·x + e, its
/// coefficients blended between α = 0 and α = 1 by (1 − α)².
float lambdaFit(float x, float alpha) {
    const float t = (1.f - alpha) * (1.f - alpha);
    const float a = glm::mix(21.5473f, 25.3245f, t), b = glm::mix(3.82987f, 3.32435f, t), c = glm::mix(0.19823f, 0.16801f, t),
                d = glm::mix(-1.97760f, -1.27393f, t), e = glm::mix(-4.32054f, -4.85967f, t);
    return a / (1.f + b * std::pow(x, c)) + d * x + e;
}

float lambdaSheen(float cosT, float alpha) {
    return std::abs(cosT) < 0.5f ? std::exp(lambdaFit(cosT, alpha)) : std::exp(2.f * lambdaFit(0.5f, alpha) - lambdaFit(1.f - cosT, alpha));
}

}  // namespace

float sheenVisibility(float nl, float nv, float alpha) {
    const float den = (1.f + lambdaSheen(nv, alpha) + lambdaSheen(nl, alpha)) * 4.f * nv * nl;
    return den > 0.f ? std::min(1.f / den, 1.f) : 0.f;
}

float sheenLobe(const Vec3& n, const Vec3& v, const Vec3& l, float alpha) {
    const float nl = glm::dot(n, l), nv = glm::dot(n, v);
    if (!(nl > 0.f) || !(nv > 0.f)) return 0.f;
    Vec3 h = v + l;
    const float hl = glm::length(h);
    if (!(hl > 0.f)) return 0.f;
    return charlieD(std::clamp(glm::dot(n, h) / hl, 0.f, 1.f), alpha) * sheenVisibility(nl, nv, alpha);
}

float sheenAlbedoQuadrature(float nv, float roughness, int thetaSteps, int phiSteps) {
    // Midpoints in cos θ (so dω = d(cos θ)·dφ needs no Jacobian) and in φ over [0, π], doubled
    // by the lobe's symmetry about the plane of n and v.
    const float alpha = sheenAlpha(roughness);
    nv = std::clamp(nv, 1e-4f, 1.f);
    const Vec3 n(0.f, 0.f, 1.f), v(std::sqrt(1.f - nv * nv), 0.f, nv);
    double sum = 0.0;
    for (int i = 0; i < thetaSteps; ++i) {
        const float c = (i + 0.5f) / float(thetaSteps), s = std::sqrt(1.f - c * c);
        for (int j = 0; j < phiSteps; ++j) {
            const float phi = kPi * (j + 0.5f) / float(phiSteps);
            const Vec3 l(s * std::cos(phi), s * std::sin(phi), c);
            sum += double(sheenLobe(n, v, l, alpha)) * c;
        }
    }
    return float(sum * 2.0 * double(kPi) / (double(thetaSteps) * double(phiSteps)));
}

namespace {

constexpr int kSheenLut = 32;  // roughness rows (kMinSheenRoughness … 1) × n·v columns (0 … 1)

/// E at the table's nodes, computed once by quadrature (about 5 million lobe evaluations, a few
/// tens of milliseconds) when the first sheen is shaded.
const std::array<float, kSheenLut * kSheenLut>& sheenLut() {
    static std::array<float, kSheenLut * kSheenLut> table;
    static std::once_flag once;
    std::call_once(once, [] {
        for (int j = 0; j < kSheenLut; ++j) {
            const float r = kMinSheenRoughness + (1.f - kMinSheenRoughness) * float(j) / (kSheenLut - 1);
            for (int i = 0; i < kSheenLut; ++i)
                table[size_t(j * kSheenLut + i)] = sheenAlbedoQuadrature(std::max(1e-3f, float(i) / (kSheenLut - 1)), r);
        }
    });
    return table;
}

}  // namespace

float sheenAlbedo(float nv, float roughness) {
    const auto& t = sheenLut();
    nv = std::clamp(std::isfinite(nv) ? nv : 0.f, 0.f, 1.f);
    const float r = std::clamp(std::isfinite(roughness) ? roughness : 1.f, kMinSheenRoughness, 1.f);
    const float x = nv * (kSheenLut - 1), y = (r - kMinSheenRoughness) / (1.f - kMinSheenRoughness) * (kSheenLut - 1);
    const int i0 = std::min(int(x), kSheenLut - 2), j0 = std::min(int(y), kSheenLut - 2);
    const float fx = x - i0, fy = y - j0;
    auto at = [&](int j, int i) { return t[size_t(j * kSheenLut + i)]; };
    const float lo = glm::mix(at(j0, i0), at(j0, i0 + 1), fx), hi = glm::mix(at(j0 + 1, i0), at(j0 + 1, i0 + 1), fx);
    return glm::mix(lo, hi, fy);
}

namespace {
float max3(const Color& c) { return std::max({c.r, c.g, c.b}); }
}  // namespace

Color sheenDirect(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const Color& base, const Color& irradiance) {
    const float m = max3(s.sheenColor);
    if (!(m > 0.f)) return base;
    const float nv = glm::dot(n, v), nl = glm::dot(n, l);
    const float scaling =
        std::clamp(std::min(1.f - m * sheenAlbedo(nv, s.sheenRoughness), 1.f - m * sheenAlbedo(nl, s.sheenRoughness)), 0.f, 1.f);
    const float lobe = sheenLobe(n, v, l, sheenAlpha(s.sheenRoughness));
    return s.sheenColor * irradiance * (lobe * std::max(nl, 0.f)) + base * scaling;
}

Color sheenEnvironment(const Surface& s, float nv, const Color& base, const Color& radiance) {
    const float m = max3(s.sheenColor);
    if (!(m > 0.f)) return base;
    const float e = sheenAlbedo(nv, s.sheenRoughness);
    return base * std::clamp(1.f - m * e, 0.f, 1.f) + s.occlusion * e * s.sheenColor * radiance;
}

}  // namespace rf::pbr
