#pragma once
/// Surface description for the Whitted model: the seed's ambient/Lambert/Phong coefficients,
/// mirror reflection, and a dielectric for refraction.
#include <algorithm>
#include <cmath>
#include <string>

#include "engine/util/vec_math.h"

namespace rf {

enum class AlphaMode { Opaque, Mask, Blend };

/// 2D affine UV transform (KHR_texture_transform): uv' = offset + R(rotation)·(scale ⊙ uv).
struct TextureTransform {
    Vec2 offset{0.f};
    float rotation = 0.f;
    Vec2 scale{1.f};
    int texCoord = 0;
    bool identity() const { return offset == Vec2(0.f) && rotation == 0.f && scale == Vec2(1.f); }
};

/// KHR_materials_volume's absorption σ per unit length: light that travels d inside keeps
/// attenuationColor^(d / distance) = exp(−σ·d) (Beer–Lambert); distance 0 or infinite: none. A
/// colour channel of 0 absorbs everything beyond the surface (σ capped so that exp(−σ·d) stays 0
/// without an infinity times a zero distance).
inline Color volumeAbsorption(const Color& attenuationColor, double distance) {
    Color sigma(0.f);
    if (distance > 0.0 && std::isfinite(distance))
        for (int i = 0; i < 3; ++i)
            sigma[i] = float(std::min(-std::log(std::max(double(attenuationColor[i]), 1e-30)), 1e30) / distance);
    return sigma;
}

struct Material {
    std::string name;
    Color color{0.8f};          ///< base colour (linear); checker: the first colour
    Color color2{0.2f};         ///< checker: the second colour
    float checkerScale = 0.f;   ///< > 0 turns on a 3D checker with cells of this size
    float ambient = 0.1f;       ///< k_amb
    float diffuse = 0.9f;       ///< k_dif
    float specular = 0.f;       ///< k_spec
    float shininess = 32.f;     ///< Phong exponent n
    float reflection = 0.f;     ///< mirror weight
    float transmission = 0.f;   ///< weight of the refracted ray (before Fresnel)
    float ior = 1.5f;           ///< index of refraction for transmission
    Color emission{0.f};
    bool doubleSided = true;
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alpha = 1.f;          ///< base colour alpha factor
    float alphaCutoff = 0.5f;
    int baseColorTexture = -1;  ///< index into Scene::textures
    TextureTransform baseColorTransform;
    int normalTexture = -1;
    float normalScale = 1.f;
    TextureTransform normalTransform;

    /// glTF metallic-roughness (engine/integrators/material_gltf.h): the tracer shades with the glTF BRDF
    /// and the Phong coefficients above (ambient, diffuse, specular, shininess, reflection) are
    /// not used. color is the base colour factor, emission the emissive factor × strength.
    bool gltfPbr = false;
    float metallic = 1.f;
    float roughness = 1.f;
    float specularWeight = 1.f;  ///< KHR_materials_specular's specularFactor
    int metallicRoughnessTexture = -1;  ///< linear; G roughness, B metallic
    TextureTransform metallicRoughnessTransform;
    int occlusionTexture = -1;  ///< linear; R
    float occlusionStrength = 1.f;
    TextureTransform occlusionTransform;
    int emissiveTexture = -1;  ///< sRGB; multiplies emission
    TextureTransform emissiveTransform;

    /// KHR_materials_unlit: the base colour is the radiance, no light enters.
    bool unlit = false;
    /// KHR_materials_clearcoat: a dielectric coat (f0 0.04) of this weight and roughness, each
    /// times its texture (R and G), over the base, with its own normal texture.
    float clearcoat = 0.f;
    float clearcoatRoughness = 0.f;
    int clearcoatTexture = -1;  ///< linear; R
    TextureTransform clearcoatTransform;
    int clearcoatRoughnessTexture = -1;  ///< linear; G
    TextureTransform clearcoatRoughnessTransform;
    int clearcoatNormalTexture = -1;
    float clearcoatNormalScale = 1.f;
    TextureTransform clearcoatNormalTransform;
    /// KHR_materials_pbrSpecularGlossiness with a texture (specular_glossiness.h): converted at
    /// each shading point from the diffuse colour (color × baseColorTexture, which hold the
    /// diffuse factor and texture) and sgSpecular, sgGlossiness × the texture's sRGB RGB and A.
    bool specularGlossiness = false;
    Color sgSpecular{1.f};
    float sgGlossiness = 1.f;
    int specularGlossinessTexture = -1;
    TextureTransform specularGlossinessTransform;
    /// KHR_materials_sheen: colour and roughness factors, times their textures (sRGB RGB; the
    /// roughness texture's alpha).
    Color sheenColor{0.f};
    float sheenRoughness = 0.f;
    int sheenColorTexture = -1;
    TextureTransform sheenColorTransform;
    int sheenRoughnessTexture = -1;
    TextureTransform sheenRoughnessTransform;
    /// KHR_materials_volume (with transmission): a thickness above 0 (factor × the texture's G)
    /// makes the mesh a volume whose inside absorbs σ per unit length, σ = −ln(attenuationColor)
    /// / attenuationDistance (0 when the distance is infinite), along every path inside it.
    float thickness = 0.f;
    int thicknessTexture = -1;
    TextureTransform thicknessTransform;
    Color attenuation{0.f};
    /// KHR_materials_dispersion (with transmission): 20/V_d; above 0 a refracted ray splits into
    /// one ray per colour channel, each at dispersedIor (optics.h) for its wavelength.
    float dispersion = 0.f;
    /// KHR_materials_iridescence: a thin film of weight iridescence (× the texture's R), index
    /// iridescenceIor and thickness in nanometres: iridescenceThicknessMax, or with the thickness
    /// texture mix(min, max, its G). A weight or thickness of 0 is no film.
    float iridescence = 0.f;
    float iridescenceIor = 1.3f;
    float iridescenceThicknessMin = 100.f;
    float iridescenceThicknessMax = 400.f;
    int iridescenceTexture = -1;  ///< linear; R
    TextureTransform iridescenceTransform;
    int iridescenceThicknessTexture = -1;  ///< linear; G
    TextureTransform iridescenceThicknessTransform;
    /// True where the material is a volume at all (thickness factor > 0 with transmission).
    bool volume() const { return gltfPbr && transmission > 0.f && thickness > 0.f; }
    /// True where light can pass the surface at all: it transmits, or it blends (alpha BLEND),
    /// so that shadow rays and the bounce light's rays must look at what it lets through.
    bool seesThrough() const { return transmission > 0.f || alphaMode == AlphaMode::Blend; }
};

}  // namespace rf
