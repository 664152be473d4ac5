#include "engine/materials/brdf_gltf.h"

#include <array>

#include "engine/materials/thin_film.h"

namespace rf::pbr {

float f0FromIor(float ior) {
    const float r = (ior - 1.f) / (ior + 1.f);
    return r * r;
}

Color specularF0(const Surface& s) { return glm::mix(Color(s.specular * f0FromIor(s.ior)), s.baseColor, s.metallic); }

float ggxD(float cos2, float sin2, float alpha) {
    const float a2 = alpha * alpha;
    const float d = cos2 * a2 + sin2;  // = cos²·(α² − 1) + 1 without the cancellation
    return d > 0.f ? a2 / (kPi * d * d) : 0.f;
}

float ggxD(float nh, float alpha) { return ggxD(nh * nh, std::max(0.f, (1.f - nh) * (1.f + nh)), alpha); }

float smithVisibility(float nl, float nv, float alpha) {
    const float a2 = alpha * alpha;
    const float gv = nl * std::sqrt(nv * nv * (1.f - a2) + a2);
    const float gl = nv * std::sqrt(nl * nl * (1.f - a2) + a2);
    const float den = gv + gl;
    return den > 0.f ? 0.5f / den : 0.f;
}

float schlickFresnel(float f0, float vh) {
    const float m = std::clamp(1.f - vh, 0.f, 1.f);
    const float m2 = m * m;
    return f0 + (1.f - f0) * (m2 * m2 * m);
}

Color schlickFresnel(const Color& f0, float vh) {
    const float m = std::clamp(1.f - vh, 0.f, 1.f);
    const float m2 = m * m;
    return f0 + (Color(1.f) - f0) * (m2 * m2 * m);
}

Color metalMultipleScattering(const Color& f0, float eAvg) {
    const Color fAvg = f0 + (Color(1.f) - f0) * (1.f / 21.f);
    return fAvg * fAvg * eAvg / (Color(1.f) - fAvg * (1.f - eAvg));
}

ViewTerms viewTerms(const Surface& s, const Vec3& n, const Vec3& v) {
    ViewTerms vt;
    const float nv = glm::dot(n, v);
    if (!(nv > 0.f) || s.metallic >= 1.f || s.transmission >= 1.f) return vt;  // evalBrdf needs neither
    const float f0 = f0FromIor(s.ior), w = s.specular;
    vt.diffuseOut = 1.f - w * dielectricAlbedo(f0, s.roughness, nv);
    vt.diffuseAvg = std::max(1e-4f, 1.f - w * dielectricAlbedoAverage(f0, s.roughness));
    if (s.iridescence > 0.f) {
        vt.filmOut = Color(1.f) - w * s.film.dielectric * singleScatterAlbedo(specularScaleBias(nv, s.roughness));
        vt.filmAvg = glm::max(Color(1e-4f), Color(1.f) - w * s.film.dielectricAvg);
    }
    return vt;
}

Color filmDielectricFresnel(const Surface& s, float cosTheta) {
    return thinFilmFresnel(cosTheta, s.iridescenceIor, s.iridescenceThickness, std::max(s.ior, 1.f));
}

Color filmMetalFresnel(const Surface& s, float cosTheta) {
    const Color baseIor(iorFromF0(s.baseColor.r), iorFromF0(s.baseColor.g), iorFromF0(s.baseColor.b));
    return thinFilmFresnel(cosTheta, s.iridescenceIor, s.iridescenceThickness, baseIor);
}

void prepareFilm(Surface& s, float nv) {
    Surface::FilmTerms& f = s.film;
    f = {};
    if (!(s.iridescence > 0.f)) return;
    if (s.metallic > 0.f) f.metal = filmMetalFresnel(s, nv);
    if (s.metallic < 1.f) {
        f.dielectric = filmDielectricFresnel(s, nv);
        // The film layer's cosine-weighted mean albedo, which the coupled diffuse divides by
        // (the film's colour varies with the angle), by quadrature: a pure function of the four
        // numbers below, so each thread keeps the last one (a material without textures computes
        // it once per thread; the result is the same to the bit either way).
        struct AvgCache {
            float ior = -1.f, filmIor = -1.f, thickness = -1.f, roughness = -1.f;
            Color avg{0.f};
        };
        thread_local AvgCache cache;
        if (cache.ior != s.ior || cache.filmIor != s.iridescenceIor || cache.thickness != s.iridescenceThickness ||
            cache.roughness != s.roughness) {
            constexpr int kSteps = 32;
            Color sum(0.f);
            for (int i = 0; i < kSteps; ++i) {
                const float mu = (i + 0.5f) / kSteps;
                sum += filmDielectricFresnel(s, mu) * (singleScatterAlbedo(specularScaleBias(mu, s.roughness)) * mu);
            }
            cache = {s.ior, s.iridescenceIor, s.iridescenceThickness, s.roughness, sum * (2.f / kSteps)};
        }
        f.dielectricAvg = cache.avg;
    }
}

namespace {

/// evalBrdf for a surface with a film: the film's Fresnel (thin_film.h) in its share of the
/// metal's and the dielectric's Schlick terms; the coupled diffuse below the dielectric layer
/// mixed the same way, the film's share coupled to the film's own albedo per channel. The film's
/// Fresnel is the one at the view, n·v (s.film), as the Khronos sample viewer evaluates it, not
/// at v·h: the lobe's albedo is then exactly that Fresnel × (A + B), the albedo the coupled
/// diffuse leaves room for (at v·h a rough white film reflected up to 1.04 of what arrives).
Color evalBrdfFilm(const Surface& s, float nl, float vh, float dv, const ViewTerms& vt) {
    const float k = s.iridescence, f0 = f0FromIor(s.ior);
    Color metal(0.f), dielectric(0.f);
    if (s.metallic > 0.f) metal = (1.f - k) * schlickFresnel(s.baseColor, vh) + k * s.film.metal;
    if (s.metallic < 1.f) dielectric = (1.f - k) * schlickFresnel(f0, vh) + k * s.film.dielectric;
    const Color spec = (s.metallic * metal + (1.f - s.metallic) * s.specular * dielectric) * dv;
    if (s.metallic >= 1.f || s.transmission >= 1.f) return spec;
    const float base = vt.diffuseOut * (1.f - s.specular * dielectricAlbedo(f0, s.roughness, nl)) / vt.diffuseAvg;
    const Color filmIn = Color(1.f) - s.specular * filmDielectricFresnel(s, nl) * singleScatterAlbedo(specularScaleBias(nl, s.roughness));
    const Color couple = (1.f - k) * base + k * vt.filmOut * filmIn / vt.filmAvg;
    return (1.f - s.metallic) * (1.f - s.transmission) * couple * s.baseColor * (1.f / kPi) + spec;
}

}  // namespace

Color evalBrdf(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l) { return evalBrdf(s, n, v, l, viewTerms(s, n, v)); }

Color evalBrdf(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const ViewTerms& vt) {
    const float nl = glm::dot(n, l), nv = glm::dot(n, v);
    if (!(nl > 0.f) || !(nv > 0.f)) return Color(0.f);
    Vec3 h = v + l;
    const float hl = glm::length(h);
    if (!(hl > 0.f)) return Color(0.f);
    h /= hl;
    const float nh = std::max(glm::dot(n, h), 0.f), vh = std::max(glm::dot(v, h), 0.f);
    const Vec3 nxh = glm::cross(n, h);
    const float alpha = std::max(alphaFromRoughness(s.roughness), kMinAlpha);
    const float dv = ggxD(nh * nh, glm::dot(nxh, nxh), alpha) * smithVisibility(nl, nv, alpha);
    if (s.iridescence > 0.f) return evalBrdfFilm(s, nl, vh, dv, vt);
    // The metal's and the dielectric's Fresnel-weighted lobes, mixed by metallic; the
    // dielectric's Fresnel layer weighs `specular` (KHR_materials_specular; 1 without it).
    const float f0 = f0FromIor(s.ior);
    const Color fresnel = s.metallic * schlickFresnel(s.baseColor, vh) + Color((1.f - s.metallic) * s.specular * schlickFresnel(f0, vh));
    const Color spec = fresnel * dv;
    if (s.metallic >= 1.f || s.transmission >= 1.f) return spec;
    const float couple = vt.diffuseOut * (1.f - s.specular * dielectricAlbedo(f0, s.roughness, nl)) / vt.diffuseAvg;
    const Color diffuse = (1.f - s.metallic) * (1.f - s.transmission) * couple * s.baseColor * (1.f / kPi);
    return diffuse + spec;
}

Color directLight(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const Color& irradiance) {
    return directLight(s, n, v, l, irradiance, viewTerms(s, n, v));
}

Color directLight(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const Color& irradiance,
                  const ViewTerms& vt) {
    const float nl = glm::dot(n, l);
    if (!(nl > 0.f)) return Color(0.f);
    return evalBrdf(s, n, v, l, vt) * irradiance * nl;
}

namespace {
constexpr float kCoatF0 = 0.04f;  // the coat's ior is 1.5 (the extension fixes it)
}

Color clearcoatDirect(const Surface& s, const Vec3& nc, const Vec3& v, const Vec3& l, const Color& base, const Color& irradiance) {
    if (!(s.clearcoat > 0.f)) return base;
    Vec3 h = v + l;
    const float hl = glm::length(h);
    if (!(hl > 0.f)) return base;
    h /= hl;
    const float fc = s.clearcoat * schlickFresnel(kCoatF0, std::max(glm::dot(v, h), 0.f));
    const float nl = glm::dot(nc, l), nv = glm::dot(nc, v);
    Color coat(0.f);
    if (nl > 0.f && nv > 0.f) {
        const float alpha = std::max(alphaFromRoughness(s.clearcoatRoughness), kMinAlpha);
        const float nh = std::max(glm::dot(nc, h), 0.f);
        const Vec3 nxh = glm::cross(nc, h);
        coat = Color(fc * ggxD(nh * nh, glm::dot(nxh, nxh), alpha) * smithVisibility(nl, nv, alpha) * nl) * irradiance;
    }
    return (1.f - fc) * base + coat;
}

Color clearcoatEnvironment(const Surface& s, float ncv, const Color& base, const Color& coatRadiance) {
    if (!(s.clearcoat > 0.f)) return base;
    const Vec2 ab = specularScaleBias(ncv, s.clearcoatRoughness);
    const float fv = s.clearcoat * schlickFresnel(kCoatF0, std::clamp(ncv, 0.f, 1.f));
    return (1.f - fv) * base + s.occlusion * s.clearcoat * (kCoatF0 * ab.x + ab.y) * coatRadiance;
}

MetallicRoughness metallicRoughnessFromTexel(float metallicFactor, float roughnessFactor, const Vec4& texel) {
    return {metallicFactor * texel.b, roughnessFactor * texel.g};
}

float occlusionFromTexel(float strength, const Vec4& texel) { return 1.f + strength * (texel.r - 1.f); }

Vec2 hammersley(uint32_t i, uint32_t n) {
    uint32_t bits = i;
    bits = (bits << 16u) | (bits >> 16u);
    bits = ((bits & 0x55555555u) << 1u) | ((bits & 0xAAAAAAAAu) >> 1u);
    bits = ((bits & 0x33333333u) << 2u) | ((bits & 0xCCCCCCCCu) >> 2u);
    bits = ((bits & 0x0F0F0F0Fu) << 4u) | ((bits & 0xF0F0F0F0u) >> 4u);
    bits = ((bits & 0x00FF00FFu) << 8u) | ((bits & 0xFF00FF00u) >> 8u);
    return Vec2((i + 0.5f) / float(n), float(bits) * 2.3283064365386963e-10f);
}

Vec3 sampleGgxHalfVector(float alpha, float u1, float u2) {
    // Inverting the CDF of D(h)·cos θh over cos² θh.
    const float a2 = alpha * alpha;
    const float den = 1.f + (a2 - 1.f) * u1;
    const float cos2 = den > 0.f ? std::clamp((1.f - u1) / den, 0.f, 1.f) : 1.f;
    const float cosT = std::sqrt(cos2), sinT = std::sqrt(1.f - cos2);
    const float phi = 2.f * kPi * u2;
    return Vec3(sinT * std::cos(phi), sinT * std::sin(phi), cosT);
}

Vec2 integrateScaleBias(float nv, float alpha) {
    // The lobe's albedo is ∫ F·D·V·(n·l) dω = f0·A + B with A = ∫(1 − Fc)w, B = ∫Fc·w and
    // Fc = (1 − v·h)⁵, by quadrature over GGX half vectors.
    constexpr uint32_t kSamples = 1024;
    const Vec3 v(std::sqrt(std::max(0.f, 1.f - nv * nv)), 0.f, nv);
    double a = 0.0, b = 0.0;
    for (uint32_t i = 0; i < kSamples; ++i) {
        const Vec2 u = hammersley(i, kSamples);
        const Vec3 h = sampleGgxHalfVector(alpha, u.x, u.y);
        const float vh = glm::dot(v, h);
        const Vec3 l = 2.f * vh * h - v;
        if (l.z <= 0.f || vh <= 0.f) continue;
        // f·cos/pdf with pdf(l) = D·(n·h)/(4 v·h): the D cancels.
        const float w = smithVisibility(l.z, nv, alpha) * 4.f * l.z * vh / h.z;
        const float fc = schlickFresnel(0.f, vh);
        a += (1.f - fc) * w;
        b += fc * w;
    }
    return Vec2(float(a / kSamples), float(b / kSamples));
}

Vec2 integrateScaleBiasNode(int roughnessRow, int nvColumn) {
    const float nv = std::max(1e-3f, float(nvColumn) / (kScaleBiasLutSize - 1));
    const float r = float(roughnessRow) / (kScaleBiasLutSize - 1);
    return integrateScaleBias(nv, alphaFromRoughness(r));
}

namespace {

constexpr int kLutSize = kScaleBiasLutSize;
using AverageLut = std::array<Vec2, kLutSize>;

// integrateScaleBiasNode(j, i) at row j, column i, written out by tests/engine/materials/brdf_lut_gen
// (a million GGX samples, 200 million instructions that every process spent at start-up).
// BrdfLut.ShippedTableIsTheQuadrature checks it against the quadrature.
constexpr float kScaleBiasTable[kLutSize * kLutSize][2] = {
#include "engine/materials/brdf_lut_table.inc"
};

Vec2 lutNode(size_t k) { return Vec2(kScaleBiasTable[k][0], kScaleBiasTable[k][1]); }

/// The table column left of n·v ∈ [0, 1] and the weight of the one right of it.
struct LutColumn {
    int i0;
    float fx;
};
LutColumn lutColumn(float nv) {
    const float x = nv * (kLutSize - 1);
    const int i0 = std::min(int(x), kLutSize - 2);
    return {i0, x - i0};
}

/// A row of the table at n·v (in column c); roughness row 0 is a mirror and so exact in closed
/// form.
Vec2 lutRow(int j, float nv, LutColumn c) {
    if (j == 0) {
        const float fc = schlickFresnel(0.f, nv);
        return Vec2(1.f - fc, fc);
    }
    const size_t k = size_t(j) * kLutSize + size_t(c.i0);
    return glm::mix(lutNode(k), lutNode(k + 1), c.fx);
}

/// Per roughness row: 2∫(A, B)(μ) μ dμ over the interpolated row, so E_avg matches the E the
/// BRDF uses (the coupled diffuse then integrates to exactly 1 − E(n·v)).
const AverageLut& averageLut() {
    static const AverageLut avg = [] {
        AverageLut t{};
        constexpr int kSteps = 1024;
        for (int j = 0; j < kLutSize; ++j) {
            Vec2 sum(0.f);
            for (int i = 0; i < kSteps; ++i) {
                const float mu = (i + 0.5f) / kSteps;
                sum += lutRow(j, mu, lutColumn(mu)) * mu;
            }
            t[size_t(j)] = sum * (2.f / kSteps);
        }
        return t;
    }();
    return avg;
}

/// Row index and weight for a roughness in [0, 1].
int rowOf(float roughness, float& frac) {
    roughness = std::clamp(std::isfinite(roughness) ? roughness : 1.f, 0.f, 1.f);
    const float y = roughness * (kLutSize - 1);
    const int j0 = std::min(int(y), kLutSize - 2);
    frac = y - j0;
    return j0;
}

}  // namespace

Vec2 scaleBiasLutEntry(int roughnessRow, int nvColumn) {
    return lutNode(size_t(roughnessRow) * kLutSize + size_t(nvColumn));
}

Vec2 specularScaleBias(float nv, float roughness) {
    nv = std::clamp(std::isfinite(nv) ? nv : 0.f, 0.f, 1.f);
    float fy;
    const int j0 = rowOf(roughness, fy);
    const LutColumn c = lutColumn(nv);  // both rows share it
    return glm::mix(lutRow(j0, nv, c), lutRow(j0 + 1, nv, c), fy);
}

float dielectricAlbedo(float f0, float roughness, float nv) {
    const Vec2 ab = specularScaleBias(nv, roughness);
    return f0 * ab.x + ab.y;
}

float dielectricAlbedoAverage(float f0, float roughness) {
    float fy;
    const int j0 = rowOf(roughness, fy);
    const AverageLut& t = averageLut();
    const Vec2 ab = glm::mix(t[size_t(j0)], t[size_t(j0) + 1], fy);
    return f0 * ab.x + ab.y;
}

Color specularAlbedo(const Surface& s, float nv) { return specularAlbedo(s, specularScaleBias(nv, s.roughness)); }

Color specularAlbedo(const Surface& s, Vec2 ab) {
    if (s.iridescence > 0.f) {
        // The film's share reflects its Fresnel at n·v over the lobe's albedo for F = 1.
        const float k = s.iridescence, e = singleScatterAlbedo(ab);
        const Color metal = (1.f - k) * (s.baseColor * ab.x + Color(ab.y)) + k * e * s.film.metal;
        const Color dielectric = s.specular * ((1.f - k) * Color(f0FromIor(s.ior) * ab.x + ab.y) + k * e * s.film.dielectric);
        return s.metallic * metal + (1.f - s.metallic) * dielectric;
    }
    const float dielectric = s.specular * (f0FromIor(s.ior) * ab.x + ab.y);
    return s.metallic * (s.baseColor * ab.x + Color(ab.y)) + Color((1.f - s.metallic) * dielectric);
}

Vec3 dominantDirection(const Vec3& n, const Vec3& r, float roughness) {
    if (!(roughness > 0.f)) return r;
    const float a = std::min(alphaFromRoughness(roughness), 1.f);
    const Vec3 m = glm::mix(n, r, (1.f - a) * (std::sqrt(1.f - a) + a));
    const float len = glm::length(m);
    return len > 1e-6f ? m / len : n;
}

Color metalMultipleScatteringAlbedo(const Surface& s, Vec2 ab) {
    if (!(s.metallic > 0.f)) return Color(0.f);
    const float eAvg = dielectricAlbedoAverage(1.f, s.roughness);
    if (!(eAvg < 1.f - 1e-4f)) return Color(0.f);  // a mirror loses nothing
    // Under a film, the further bounces see the film's reflectance in its share.
    const Color f0 = s.iridescence > 0.f ? glm::mix(s.baseColor, s.film.metal, s.iridescence) : s.baseColor;
    return s.metallic * std::max(0.f, 1.f - singleScatterAlbedo(ab)) * metalMultipleScattering(f0, eAvg);
}

Color environmentLight(const Surface& s, float nv, const Color& specularRadiance, const Color& diffuseRadiance) {
    return environmentLight(s, specularScaleBias(nv, s.roughness), specularRadiance, diffuseRadiance);
}

Color environmentLight(const Surface& s, Vec2 ab, const Color& specularRadiance, const Color& diffuseRadiance) {
    if (s.iridescence > 0.f) {
        // As below, with the dielectric layer's albedo per channel (the film's share coloured).
        const Color ed = s.specular * ((1.f - s.iridescence) * Color(f0FromIor(s.ior) * ab.x + ab.y) +
                                       s.iridescence * singleScatterAlbedo(ab) * s.film.dielectric);
        Color spec = specularAlbedo(s, ab) * specularRadiance;
        if (s.metallic > 0.f) spec += metalMultipleScatteringAlbedo(s, ab) * diffuseRadiance;
        const Color diffuse = (1.f - s.metallic) * (1.f - s.transmission) * (Color(1.f) - ed) * s.baseColor * diffuseRadiance;
        return s.occlusion * (spec + diffuse);
    }
    const float ed = s.specular * (f0FromIor(s.ior) * ab.x + ab.y);
    Color spec = specularAlbedo(s, ab) * specularRadiance;
    // The metal's multiple scattering leaves in all directions, as its lobe (1 − E(n·l)) is
    // nearly a cosine one: lit by the irradiance, not by the prefiltered mirror direction.
    if (s.metallic > 0.f) spec += metalMultipleScatteringAlbedo(s, ab) * diffuseRadiance;
    // The coupled diffuse layer under light arriving evenly: (1 − E(n·v))·c times irradiance/π.
    const Color diffuse = (1.f - s.metallic) * (1.f - s.transmission) * (1.f - ed) * s.baseColor * diffuseRadiance;
    return s.occlusion * (spec + diffuse);
}

}  // namespace rf::pbr
