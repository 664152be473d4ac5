#pragma once
/// KHR_materials_sheen's layer over the glTF BRDF, as the extension's implementation notes give
/// it: the "Charlie" fibre distribution (Estevez and Kulla 2017) with its fitted visibility, no
/// Fresnel, and the base below it scaled by what the sheen's directional albedo E leaves:
/// f = f_sheen + f_base · min(1 − max3(sheenColor)·E(n·v), 1 − max3(sheenColor)·E(n·l)).
/// A sheen colour of 0 leaves the base exactly as it was.
#include "engine/util/vec_math.h"

namespace rf::pbr {

struct Surface;

/// Sheen roughness below this is shaded as this: the distribution's exponent 1/α² would pass
/// 10⁴ and its peak one ulp of the cosine wide.
constexpr float kMinSheenRoughness = 0.07f;
/// α = max(roughness, kMinSheenRoughness)², as the extension squares it.
float sheenAlpha(float roughness);
/// D = (2 + 1/α)·sin^(1/α) θh / 2π; normalized: ∫ D(h)·cos θh dω = 1.
float charlieD(float nh, float alpha);
/// V = 1 / ((1 + Λ(n·v) + Λ(n·l))·4·n·v·n·l) with the extension's fitted Λ, clamped to [0, 1].
float sheenVisibility(float nl, float nv, float alpha);
/// The sheen lobe f_sheen/sheenColor = D·V for unit n, v, l (0 below the surface).
float sheenLobe(const Vec3& n, const Vec3& v, const Vec3& l, float alpha);

/// E(μ): the share of light from a uniform sky the lobe (sheen colour 1) reflects towards a
/// viewer at cosine μ, tabulated over (μ, roughness) on first use and interpolated.
float sheenAlbedo(float nv, float roughness);
/// The same by direct quadrature over the hemisphere (what the table holds at its nodes).
float sheenAlbedoQuadrature(float nv, float roughness, int thetaSteps = 96, int phiSteps = 48);

/// Direct light: `base` (the base layer's reflected radiance for this light) becomes
/// sheenColor·D·V·(n·l)·E_light + base·scaling, scaling the min of the view's and the light's.
Color sheenDirect(const Surface& s, const Vec3& n, const Vec3& v, const Vec3& l, const Color& base, const Color& irradiance);
/// Environment light: base·(1 − max3(sheenColor)·E(n·v)) + occlusion·sheenColor·E(n·v)·radiance,
/// `radiance` the light the wide lobe gathers (the environment's cosine-weighted average).
Color sheenEnvironment(const Surface& s, float nv, const Color& base, const Color& radiance);

}  // namespace rf::pbr
