#include "engine/integrators/material_gltf.h"

#include "engine/materials/material_eval.h"
#include "engine/scene/scene.h"
#include "engine/materials/specular_glossiness.h"

namespace rf {

GltfSample gltfSample(const Scene& scene, const SurfaceInteraction& si) {
    const Material& m = scene.materials[si.material];
    GltfSample g;
    pbr::Surface& s = g.surface;
    s.baseColor = baseColor(scene, si);  // factor × texture (× COLOR_0 where the mesh has it)
    s.metallic = m.metallic;
    s.roughness = m.roughness;
    s.ior = m.ior;
    s.specular = m.specularWeight;
    auto texel = [&](int tex, const TextureTransform& t) {
        return sampleTexture(scene.textures[size_t(tex)], textureUv(t, si.uv, si.uv1), textureFootprint(t, si.uvArea));
    };
    if (m.metallicRoughnessTexture >= 0) {
        const pbr::MetallicRoughness mr =
            pbr::metallicRoughnessFromTexel(m.metallic, m.roughness, texel(m.metallicRoughnessTexture, m.metallicRoughnessTransform));
        s.metallic = std::clamp(mr.metallic, 0.f, 1.f);
        s.roughness = std::clamp(mr.roughness, 0.f, 1.f);
    }
    if (m.specularGlossiness) {
        Color specular = m.sgSpecular;
        float glossiness = m.sgGlossiness;
        if (m.specularGlossinessTexture >= 0) {
            const Vec4 t = texel(m.specularGlossinessTexture, m.specularGlossinessTransform);
            specular *= Color(t);
            glossiness *= t.a;
        }
        const SpecularGlossinessAsMetallic mr = convertSpecularGlossiness(s.baseColor, specular, glossiness);
        s.baseColor = mr.baseColor;
        s.metallic = mr.metallic;
        s.roughness = mr.roughness;
    }
    if (m.occlusionTexture >= 0)
        s.occlusion = std::clamp(pbr::occlusionFromTexel(m.occlusionStrength, texel(m.occlusionTexture, m.occlusionTransform)), 0.f, 1.f);
    g.emission = m.emission;
    if (m.emissiveTexture >= 0 && m.emission != Color(0.f)) g.emission *= Color(texel(m.emissiveTexture, m.emissiveTransform));
    // The metal has no transmission (the glTF mixing: mix(dielectric, metal, metallic)).
    g.transmission = m.specularGlossiness || !(m.transmission > 0.f) ? m.transmission : m.transmission * (1.f - s.metallic);
    s.transmission = g.transmission;
    g.unlit = m.unlit;
    s.clearcoat = m.clearcoat;
    s.clearcoatRoughness = m.clearcoatRoughness;
    if (m.clearcoat > 0.f && m.clearcoatTexture >= 0) s.clearcoat *= texel(m.clearcoatTexture, m.clearcoatTransform).r;
    if (m.clearcoat > 0.f && m.clearcoatRoughnessTexture >= 0)
        s.clearcoatRoughness = std::clamp(s.clearcoatRoughness * texel(m.clearcoatRoughnessTexture, m.clearcoatRoughnessTransform).g, 0.f, 1.f);
    s.sheenColor = m.sheenColor;
    s.sheenRoughness = m.sheenRoughness;
    if (m.sheenColor != Color(0.f)) {
        if (m.sheenColorTexture >= 0) s.sheenColor *= Color(texel(m.sheenColorTexture, m.sheenColorTransform));
        if (m.sheenRoughnessTexture >= 0)
            s.sheenRoughness = std::clamp(s.sheenRoughness * texel(m.sheenRoughnessTexture, m.sheenRoughnessTransform).a, 0.f, 1.f);
    }
    if (m.iridescence > 0.f) {
        // KHR_materials_iridescence: the film's weight × the texture's R, its thickness the
        // maximum or, with the thickness texture, mix(minimum, maximum, G). 0 of either: no film.
        float k = m.iridescence;
        if (m.iridescenceTexture >= 0) k *= texel(m.iridescenceTexture, m.iridescenceTransform).r;
        float thickness = m.iridescenceThicknessMax;
        if (m.iridescenceThicknessTexture >= 0)
            thickness = glm::mix(m.iridescenceThicknessMin, m.iridescenceThicknessMax,
                                 texel(m.iridescenceThicknessTexture, m.iridescenceThicknessTransform).g);
        if (k > 0.f && thickness > 0.f) {
            s.iridescence = std::min(k, 1.f);
            s.iridescenceIor = m.iridescenceIor;
            s.iridescenceThickness = thickness;
        }
    }
    return g;
}

float gltfTransmission(const Scene& scene, const SurfaceInteraction& si) {
    const Material& m = scene.materials[si.material];
    if (!(m.transmission > 0.f) || m.specularGlossiness) return m.transmission;
    float metallic = m.metallic;
    if (m.metallicRoughnessTexture >= 0) {
        const TextureTransform& t = m.metallicRoughnessTransform;
        const Vec4 texel = sampleTexture(scene.textures[size_t(m.metallicRoughnessTexture)], textureUv(t, si.uv, si.uv1),
                                         textureFootprint(t, si.uvArea));
        metallic = std::clamp(pbr::metallicRoughnessFromTexel(m.metallic, m.roughness, texel).metallic, 0.f, 1.f);
    }
    return m.transmission * (1.f - metallic);
}

float gltfCoverage(const Scene& scene, const SurfaceInteraction& si) {
    const Material& m = scene.materials[si.material];
    if (m.alphaMode != AlphaMode::Blend) return 1.f;
    float alpha = 1.f;
    baseColor(scene, si, &alpha);
    return std::isfinite(alpha) ? std::clamp(alpha, 0.f, 1.f) : 1.f;
}

Color gltfPassing(const Scene& scene, const SurfaceInteraction& si, float F) {
    const Material& m = scene.materials[si.material];
    const float cover = gltfCoverage(scene, si);
    const float transmission = m.transmission > 0.f ? gltfTransmission(scene, si) : 0.f;
    Color through(1.f - cover);
    if (transmission > 0.f) through += cover * transmission * (1.f - F) * baseColor(scene, si);
    return through;
}

float gltfThickness(const Scene& scene, const SurfaceInteraction& si) {
    const Material& m = scene.materials[si.material];
    if (m.thicknessTexture < 0 || !(m.thickness > 0.f)) return m.thickness;
    const TextureTransform& t = m.thicknessTransform;
    return m.thickness * sampleTexture(scene.textures[size_t(m.thicknessTexture)], textureUv(t, si.uv, si.uv1),
                                       textureFootprint(t, si.uvArea)).g;
}

}  // namespace rf
