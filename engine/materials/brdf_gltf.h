#pragma once
/// The glTF 2.0 metallic-roughness BRDF (specification, Appendix B): α = roughness², GGX
/// distribution, height-correlated Smith visibility, Schlick Fresnel with f0 from the index of
/// refraction (KHR_materials_ior), Lambert diffuse, and the metal/dielectric mix. Pure functions
/// of unit vectors in one frame; the tracer supplies the frame and the light.
#include "engine/util/vec_math.h"

namespace rf::pbr {

/// What the BRDF needs at one surface point, after textures and factors are applied.
struct Surface {
    Color baseColor{1.f};  ///< linear
    float metallic = 0.f;
    float roughness = 1.f;  ///< perceptual roughness; α = roughness²
    float ior = 1.5f;       ///< dielectric f0 = ((ior − 1)/(ior + 1))²
    float occlusion = 1.f;  ///< dims environment and indirect light only, never direct light
    float specular = 1.f;   ///< KHR_materials_specular: weight of the dielectric's Fresnel layer
    float transmission = 0.f;  ///< KHR_materials_transmission: share of the diffuse base let through
    float clearcoat = 0.f;           ///< KHR_materials_clearcoat: the coat's weight (0: none)
    float clearcoatRoughness = 0.f;  ///< its perceptual roughness
    Color sheenColor{0.f};           ///< KHR_materials_sheen: the sheen's colour (0: none), brdf_sheen.h
    float sheenRoughness = 0.f;      ///< its perceptual roughness
    /// KHR_materials_iridescence: a thin film of this weight (0: none, and nothing below is
    /// read), index and thickness (nm) over the base. Its Fresnel (thin_film.h) replaces the
    /// Schlick Fresnel of the metal and of the dielectric layer in that share.
    float iridescence = 0.f;
    float iridescenceIor = 1.3f;
    float iridescenceThickness = 0.f;
    /// What the film gives at the view direction, filled by prepareFilm (which every caller of
    /// the functions below must run first on a surface with a film).
    struct FilmTerms {
        Color metal{0.f};          ///< the film's Fresnel over the metal at n·v
        Color dielectric{0.f};     ///< the film's Fresnel over the dielectric (index ior) at n·v
        Color dielectricAvg{0.f};  ///< 2∫E_f(μ)μ dμ, E_f(μ) = that Fresnel at μ × (A + B)(μ)
    } film;
};

/// Fills s.film for the view cosine nv (a surface with iridescence > 0 only).
void prepareFilm(Surface& s, float nv);
/// The film's Fresnel at cos θ over the dielectric base (index s.ior) and over the metal (the
/// index whose f0 is the base colour, per channel, as the specification converts it).
Color filmDielectricFresnel(const Surface& s, float cosTheta);
Color filmMetalFresnel(const Surface& s, float cosTheta);

/// Smallest α analytic lights see: a delta lobe would make a point light's highlight vanish (or
/// turn into 0/0). Roughness below ~0.045 shades direct light as this; mirrors still reflect.
constexpr float kMinAlpha = 2e-3f;

inline float alphaFromRoughness(float roughness) { return roughness * roughness; }
/// ((ior − 1)/(ior + 1))²: 0.04 at ior 1.5.
float f0FromIor(float ior);
/// Reflectance at normal incidence: the dielectric's f0 (× specular) and the metal's base
/// colour, mixed by metallic.
Color specularF0(const Surface& s);
/// GGX (Trowbridge–Reitz) normal distribution D(h) for cos θh = nh.
float ggxD(float nh, float alpha);
/// The same from cos² θh and sin² θh given apart: for small α, 1 − cos² θh from a float cosine
/// loses the digits the peak depends on, while |n × h|² keeps them.
float ggxD(float cos2, float sin2, float alpha);
/// Height-correlated Smith visibility V = G₂ / (4 |n·l| |n·v|).
float smithVisibility(float nl, float nv, float alpha);
/// Schlick's Fresnel with f90 = 1 for the cosine between the view and the half vector.
Color schlickFresnel(const Color& f0, float vh);
float schlickFresnel(float f0, float vh);

/// The BRDF f(v, l) (without the cosine) for unit n, v, l on the same side of the surface.
/// Zero when either direction lies below it. The metal's lobe scatters once here (as Blender
/// 3.4's default GGX, which the light-lit Cycles references use); environmentLight gives its
/// multiple scattering back. The diffuse layer receives what the specular layer's directional
/// albedo E leaves, on the way in and out (Kelemen and Szirmay-Kalos 2001): (1 − E(n·v))(1 − E(n·l))/(1 − E_avg) · c/π, which is reciprocal and conserves energy. The
/// spec's per-microfacet (1 − F(v·h)) makes a smooth white dielectric reflect 1.55 times the
/// light it receives at n·v = 0.1, and a white furnace must not glow.
Color evalBrdf(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l);

/// What evalBrdf needs of the surface and the view direction alone: the coupled diffuse's
/// 1 − w·E(n·v) and 1 − w·E_avg. A shading point computes them once for all its lights (each is
/// a table look-up in two dimensions); evalBrdf with them gives the same colour to the bit.
struct ViewTerms {
    float diffuseOut = 0.f;  ///< 1 − w·E(n·v)
    float diffuseAvg = 1.f;  ///< max(1e-4, 1 − w·E_avg)
    Color filmOut{0.f};      ///< with a film: the same for the film's layer, per channel
    Color filmAvg{1.f};
};
ViewTerms viewTerms(const Surface& s, const Vec3& n, const Vec3& v);
Color evalBrdf(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const ViewTerms& vt);

/// Reflected radiance from a light arriving along l with irradiance E (at normal incidence):
/// f · E · (n·l). Occlusion does not enter: it describes ambient visibility only.
Color directLight(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const Color& irradiance);
Color directLight(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const Color& irradiance,
                  const ViewTerms& vt);

/// KHR_materials_clearcoat over direct light: the base's reflected radiance `base` (directLight
/// at the base normal) becomes (1 − c·Fc)·base + c·Fc·D·V·(nc·l)·E, with Fc = Schlick(0.04, v·h)
/// and D, V of the coat's roughness at its normal nc, as the extension's specification layers it.
Color clearcoatDirect(const Surface& s, const Vec3& nc, const Vec3& v, const Vec3& l, const Color& base, const Color& irradiance);
/// The same under environment light: (1 − c·F(nc·v))·base + c·(0.04·A + B)·coatRadiance, the
/// coat's split sum at its roughness (coatRadiance: prefiltered around the coat's mirror ray).
Color clearcoatEnvironment(const Surface& s, float ncv, const Color& base, const Color& coatRadiance);

/// glTF's metallicRoughnessTexture: G is roughness, B is metallic, both linear, multiplied by
/// the factors. R (often occlusion in packed ORM textures) is ignored.
struct MetallicRoughness {
    float metallic = 1.f;
    float roughness = 1.f;
};
MetallicRoughness metallicRoughnessFromTexel(float metallicFactor, float roughnessFactor, const Vec4& texel);
/// glTF's occlusionTexture: 1 + strength · (R − 1).
float occlusionFromTexel(float strength, const Vec4& texel);

/// Kulla and Conty's F_ms per channel: the share of the light that the further bounces between
/// microfacets of a metal of reflectance f0 give back, for a lobe of mean albedo E_avg (F = 1):
/// its further bounces weigh F_avg each (1 for a white metal, whose F_ms is then 1).
Color metalMultipleScattering(const Color& f0, float eAvg);
/// E_ss of the lobe for F = 1, from the split sum: A + B.
inline float singleScatterAlbedo(Vec2 scaleBias) { return scaleBias.x + scaleBias.y; }

/// Where to read the environment prefiltered with n = v = r for a GGX lobe about n seen along the
/// mirror direction r: a rough lobe leans from r towards n (Lagarde and de Rousiers 2014, the
/// "dominant direction" of Frostbite and Filament): normalize(mix(n, r, (1 − α)(√(1 − α) + α))),
/// r itself for a mirror and n at roughness 1. rayfarm reads metals there (the rough ones came
/// out tinted by the environment's far side), dielectrics at r (measured worse against Cycles).
Vec3 dominantDirection(const Vec3& n, const Vec3& r, float roughness);

/// Split-sum scale and bias (Karis 2013): the GGX lobe's directional albedo is f0·A + B for
/// Schlick's Fresnel. Tabulated once, interpolated in (n·v, roughness).
Vec2 specularScaleBias(float nv, float roughness);
/// The share of light a surface reflects specularly from a uniform environment, per channel, in
/// one scattering: f0·A + B for the metal and the dielectric's Fresnel layer, mixed by metallic.
Color specularAlbedo(const Surface& s, float nv);
/// The same from specularScaleBias(n·v, s.roughness), for a caller that needs it more than once.
Color specularAlbedo(const Surface& s, Vec2 scaleBias);
/// What the metal's microfacets give back in further bounces under a uniform environment
/// (Kulla and Conty 2017): metallic·F_ms·(1 − E(n·v)), E the single-scattering albedo for F = 1;
/// the integral of their lobe F_ms·(1 − E(n·v))(1 − E(n·l))/(π(1 − E_avg)). With specularAlbedo,
/// 1 in all for a white metal at every roughness.
Color metalMultipleScatteringAlbedo(const Surface& s, Vec2 scaleBias);
/// The dielectric layer's specular albedo E(μ) and its cosine-weighted mean E_avg = 2∫E(μ)μ dμ.
float dielectricAlbedo(float f0, float roughness, float nv);
float dielectricAlbedoAverage(float f0, float roughness);
/// Reflected radiance under environment light: prefiltered specular radiance (GGX lobe around
/// the mirror direction) and diffuse irradiance/π, weighted by the split sum and the occlusion;
/// the metal's multiple scattering (metalMultipleScatteringAlbedo) reflects the irradiance.
Color environmentLight(const Surface& s, float nv, const Color& specularRadiance, const Color& diffuseRadiance);
Color environmentLight(const Surface& s, Vec2 scaleBias, const Color& specularRadiance, const Color& diffuseRadiance);

/// The split-sum table: kScaleBiasLutSize² nodes, roughness rows by n·v columns, each
/// integrateScaleBiasNode's quadrature, shipped as engine/materials/brdf_lut_table.inc (run at start-up,
/// the quadrature cost every process 200 million instructions, about 50 ms).
constexpr int kScaleBiasLutSize = 32;
Vec2 scaleBiasLutEntry(int roughnessRow, int nvColumn);
/// (A, B) of the GGX lobe at (n·v, α) by 1024-point Hammersley quadrature.
Vec2 integrateScaleBias(float nv, float alpha);
/// integrateScaleBias at a table node: n·v = max(10⁻³, i/31), roughness j/31.
Vec2 integrateScaleBiasNode(int roughnessRow, int nvColumn);

/// A GGX half vector about +Z sampled proportionally to D(h)·cos θh, from two uniforms in [0, 1).
Vec3 sampleGgxHalfVector(float alpha, float u1, float u2);
/// The i-th of n points of the Hammersley set in [0, 1)² (deterministic quadrature).
Vec2 hammersley(uint32_t i, uint32_t n);

}  // namespace rf::pbr
