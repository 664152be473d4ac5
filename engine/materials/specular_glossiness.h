#pragma once
/// KHR_materials_pbrSpecularGlossiness to metallic-roughness, as the Khronos glTF converter
/// does it: metallic solved from the perceived brightness of the diffuse and specular colours
/// (a dielectric's f0 being 0.04), the base colour blended from what each implies, roughness
/// 1 − glossiness. The loader converts factors with it; a material with textures is converted
/// at every shading point, so each texel gets its own metallic and roughness.
#include "engine/util/vec_math.h"

namespace rf {

struct SpecularGlossinessAsMetallic {
    Color baseColor{1.f};
    float metallic = 0.f;
    float roughness = 1.f;
};

/// diffuse, specular: linear colours in [0, 1]; glossiness in [0, 1].
SpecularGlossinessAsMetallic convertSpecularGlossiness(const Color& diffuse, const Color& specular, float glossiness);

}  // namespace rf
