#pragma once
/// The glTF metallic-roughness material at a surface point: every factor times its texture, as
/// the core specification and KHR_materials_* define them, ready for brdf_gltf.h.
#include "engine/materials/brdf_gltf.h"

namespace rf {

class Scene;
struct SurfaceInteraction;

struct GltfSample {
    pbr::Surface surface;   ///< base colour, metallic, roughness, ior, specular, occlusion
    Color emission{0.f};    ///< emissiveFactor × emissive texture (sRGB) × emissive strength
    float transmission = 0.f;
    bool unlit = false;     ///< KHR_materials_unlit: surface.baseColor is the radiance
};

/// baseColor = factor × texture (sRGB, decoded at load) × COLOR_0; metallic = factor × B and
/// roughness = factor × G of the metallicRoughness texture; occlusion = 1 + strength·(R − 1);
/// emission = emissive (factor × strength, as loaded) × the emissive texture. Every texture reads
/// its own texCoord set through its own KHR_texture_transform.
GltfSample gltfSample(const Scene& scene, const SurfaceInteraction& si);

/// KHR_materials_transmission at si as the specification mixes it: the dielectric part lets
/// light through and the metal does not, transmissionFactor × (1 − metallic), metallic the
/// factor × the metallicRoughness texture's B (specular-glossiness materials have no metallic:
/// the factor as it is). gltfSample's transmission is the same number.
float gltfTransmission(const Scene& scene, const SurfaceInteraction& si);

/// alphaMode BLEND at si: the share of the surface that is there, alpha factor × base-colour
/// texture alpha × vertex alpha in [0, 1]; the rest (1 − coverage) lets light pass unbent and
/// untinted, as blending over what is behind it does. 1 for OPAQUE and MASK materials.
float gltfCoverage(const Scene& scene, const SurfaceInteraction& si);

/// What a ray passing si straight on (a shadow ray, a bounce ray looking through) keeps: the
/// blended-away share (1 − coverage), plus on the covered share the transmission (Fresnel F at
/// the surface taken away) tinted by the base colour. 0 for an opaque surface.
Color gltfPassing(const Scene& scene, const SurfaceInteraction& si, float F);

/// KHR_materials_volume's thickness at si: factor × the thickness texture's G (0: thin-walled).
float gltfThickness(const Scene& scene, const SurfaceInteraction& si);

}  // namespace rf
