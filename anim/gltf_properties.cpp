// GltfAnimationPlayer's KHR_animation_pointer properties (gltf_animation.h): the nodes' KHR_node_visibility,
// the model's lights, materials and texture transforms, and the lens of a file camera, each set
// from its keys at a frame's time.
#include <algorithm>
#include <cmath>

#include "anim/gltf_animation.h"
#include "engine/lights/exposure.h"

namespace rf::anim {

std::vector<uint8_t> GltfAnimationPlayer::visibleNodes(const SceneGraph& g, const std::function<double(size_t)>& timeOf) const {
    std::vector<uint8_t> own(g.nodes.size(), 1);
    for (size_t i = 0; i < g.nodes.size(); ++i) own[i] = g.nodes[i].visible;
    for (const PropertyTrack& p : properties_)
        if (p.target.property == AnimProperty::NodeVisible && size_t(p.target.target) < own.size())
            own[size_t(p.target.target)] = p.track.evaluateScalar(timeOf(p.part)) != 0.0;
    // Visible only if every node above is (a cycle guard bounds the walk).
    std::vector<uint8_t> shown(g.nodes.size(), 1);
    for (size_t i = 0; i < g.nodes.size(); ++i)
        for (int n = int(i), guard = 0; n >= 0 && size_t(n) < g.nodes.size() && guard <= int(g.nodes.size()); n = g.nodes[size_t(n)].parent, ++guard)
            if (!own[size_t(n)]) {
                shown[i] = 0;
                break;
            }
    return shown;
}

void GltfAnimationPlayer::applyLights(Scene& scene, const std::vector<DMat4>& renderFromNode, const std::vector<uint8_t>& visible,
                                      const std::function<double(size_t)>& timeOf) const {
    const SceneGraph& graph = scene.geometry.models[size_t(model_)];
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        Light& L = scene.lights[i];
        if (L.model != model_ || L.node < 0 || size_t(L.node) >= renderFromNode.size()) continue;
        const size_t node = size_t(L.node);
        if (node < moving_.size() && moving_[node]) {
            // Placed as the loader places it: at the node's origin, shining down its −z.
            const DMat4& m = renderFromNode[node];
            L.position = Vec3(DVec3(m[3]));
            const DVec3 d = glm::dmat3(m) * DVec3(0.0, 0.0, -1.0);
            const double len = glm::length(d);
            if (len > 0.0 && std::isfinite(len)) L.direction = Vec3(d / len);
        }
        bool intensityKeyed = false;
        for (const PropertyTrack& p : properties_) {
            if (p.target.target != L.source) continue;
            const double at = timeOf(p.part);
            switch (p.target.property) {
                case AnimProperty::LightColor: {
                    const DVec3 c = p.track.evaluateVec3(at);
                    L.color = Color(Vec3(glm::max(c, DVec3(0.0))));
                    break;
                }
                case AnimProperty::LightIntensity:
                    // Photometric, as loaded: cd or lx at 683 lm/W.
                    L.intensity = float(std::max(0.0, p.track.evaluateScalar(at)) / double(kLumensPerWatt));
                    intensityKeyed = true;
                    break;
                case AnimProperty::LightRange: {
                    const double r = p.track.evaluateScalar(at);
                    L.range = r > 0.0 && std::isfinite(r) ? float(r) : 0.f;
                    break;
                }
                case AnimProperty::LightSpotInner:
                    L.innerCone = float(std::clamp(p.track.evaluateScalar(at), 0.0, double(kPi) / 2));
                    break;
                case AnimProperty::LightSpotOuter:
                    L.outerCone = float(std::clamp(p.track.evaluateScalar(at), 0.0, double(kPi) / 2));
                    break;
                default: break;
            }
        }
        // As the loader orders them: the outer cone no narrower than the inner one.
        if (L.type == LightType::Spot) L.outerCone = std::max(L.outerCone, L.innerCone);
        if (!visible.empty() && !visible[node]) {
            L.intensity = 0.f;
        } else if (!intensityKeyed) {
            // Shown: a light hidden at rest was loaded dark; it gives what it gives when shown.
            for (const auto& [light, shown] : graph.restHiddenLights)
                if (size_t(light) == i) L.intensity = shown;
        }
    }
}

namespace {

/// The material's transform of a texture slot.
TextureTransform* slotTransform(Material& m, TextureSlot slot) {
    switch (slot) {
        case TextureSlot::BaseColor: return &m.baseColorTransform;
        case TextureSlot::MetallicRoughness: return &m.metallicRoughnessTransform;
        case TextureSlot::Normal: return &m.normalTransform;
        case TextureSlot::Occlusion: return &m.occlusionTransform;
        case TextureSlot::Emissive: return &m.emissiveTransform;
        case TextureSlot::Clearcoat: return &m.clearcoatTransform;
        case TextureSlot::ClearcoatRoughness: return &m.clearcoatRoughnessTransform;
        case TextureSlot::ClearcoatNormal: return &m.clearcoatNormalTransform;
        case TextureSlot::SheenColor: return &m.sheenColorTransform;
        case TextureSlot::SheenRoughness: return &m.sheenRoughnessTransform;
        case TextureSlot::Iridescence: return &m.iridescenceTransform;
        case TextureSlot::IridescenceThickness: return &m.iridescenceThicknessTransform;
        case TextureSlot::Thickness: return &m.thicknessTransform;
        case TextureSlot::None: break;
    }
    return nullptr;
}

float unit(double v) { return float(std::clamp(v, 0.0, 1.0)); }
Color unitColor(const DVec3& c) { return Color(unit(c.x), unit(c.y), unit(c.z)); }

}  // namespace

void GltfAnimationPlayer::applyMaterials(Scene& scene, const std::function<double(size_t)>& timeOf) const {
    const SceneGraph& g = scene.geometry.models[size_t(model_)];
    bool changed = false;
    for (const AnimatedMaterial& am : g.animatedMaterials) {
        if (am.scene < 0 || size_t(am.scene) >= scene.materials.size()) continue;
        Material& m = scene.materials[size_t(am.scene)];
        Color emissive = am.emissiveFactor, attenuationColor = am.attenuationColor;
        float strength = am.emissiveStrength, distance = am.attenuationDistance;
        bool emission = false, volume = false;
        for (const PropertyTrack& p : properties_) {
            if (p.target.target != am.file || p.target.property < AnimProperty::BaseColor || p.target.property == AnimProperty::NodeVisible)
                continue;
            changed = true;
            const double at = timeOf(p.part);
            double v[4] = {0.0, 0.0, 0.0, 0.0};
            p.track.evaluate(at, v);
            switch (p.target.property) {
                case AnimProperty::BaseColor:
                    m.color = Color(unit(v[0]), unit(v[1]), unit(v[2]));
                    m.alpha = unit(v[3]);
                    break;
                case AnimProperty::Metallic: m.metallic = unit(v[0]); break;
                case AnimProperty::Roughness: m.roughness = unit(v[0]); break;
                case AnimProperty::Emissive: emissive = unitColor(DVec3(v[0], v[1], v[2])), emission = true; break;
                case AnimProperty::EmissiveStrength: strength = float(std::max(0.0, v[0])), emission = true; break;
                case AnimProperty::AlphaCutoff: m.alphaCutoff = float(std::max(0.0, v[0])); break;
                case AnimProperty::NormalScale: m.normalScale = float(v[0]); break;
                case AnimProperty::OcclusionStrength: m.occlusionStrength = unit(v[0]); break;
                case AnimProperty::Transmission: m.transmission = unit(v[0]); break;
                case AnimProperty::Ior: m.ior = float(std::clamp(v[0], 1.0, 10.0)); break;
                case AnimProperty::Thickness: m.thickness = float(std::max(0.0, v[0])); break;
                case AnimProperty::AttenuationColor: attenuationColor = unitColor(DVec3(v[0], v[1], v[2])), volume = true; break;
                case AnimProperty::AttenuationDistance: distance = v[0] > 0.0 && std::isfinite(v[0]) ? float(v[0]) : 0.f, volume = true; break;
                case AnimProperty::Clearcoat: m.clearcoat = unit(v[0]); break;
                case AnimProperty::ClearcoatRoughness: m.clearcoatRoughness = unit(v[0]); break;
                case AnimProperty::ClearcoatNormalScale: m.clearcoatNormalScale = float(v[0]); break;
                case AnimProperty::SheenColor: m.sheenColor = unitColor(DVec3(v[0], v[1], v[2])); break;
                case AnimProperty::SheenRoughness: m.sheenRoughness = unit(v[0]); break;
                case AnimProperty::Specular: m.specularWeight = unit(v[0]); break;
                case AnimProperty::Iridescence: m.iridescence = unit(v[0]); break;
                case AnimProperty::IridescenceIor: m.iridescenceIor = float(std::clamp(v[0], 1.0, 10.0)); break;
                case AnimProperty::IridescenceThicknessMin: m.iridescenceThicknessMin = float(std::clamp(v[0], 0.0, 1e6)); break;
                case AnimProperty::IridescenceThicknessMax: m.iridescenceThicknessMax = float(std::clamp(v[0], 0.0, 1e6)); break;
                case AnimProperty::TextureOffset:
                case AnimProperty::TextureRotation:
                case AnimProperty::TextureScale:
                    if (TextureTransform* tt = slotTransform(m, p.target.slot)) {
                        if (p.target.property == AnimProperty::TextureOffset) tt->offset = Vec2(float(v[0]), float(v[1]));
                        else if (p.target.property == AnimProperty::TextureRotation) tt->rotation = float(v[0]);
                        else tt->scale = Vec2(float(v[0]), float(v[1]));
                    }
                    break;
                default: break;
            }
        }
        if (emission) m.emission = strength * emissive;
        if (volume) m.attenuation = volumeAbsorption(attenuationColor, distance);
    }
    // The masked-triangle test keeps its own copy of the materials' alpha.
    if (changed) scene.geometry.updateMaterials(scene.materials);
}

void GltfAnimationPlayer::applyCamera(int camera, double t, Camera& lens) const {
    for (const PropertyTrack& p : properties_) {
        if (p.target.target != camera) continue;
        const double v = p.track.evaluateScalar(localTime(t, p.part));
        if (p.target.property == AnimProperty::CameraYfov) {
            if (v > 0.0 && v < double(kPi)) lens.fovDeg = float(glm::degrees(v)), lens.fovHorizontal = false;
        } else if ((p.target.property == AnimProperty::CameraYmag && !lens.fovHorizontal) ||
                   (p.target.property == AnimProperty::CameraXmag && lens.fovHorizontal)) {
            // The lens is fitted by one magnification (ymag, else xmag); pixels stay square.
            if (std::isfinite(v) && std::abs(v) > 0.0) lens.orthoHalf = float(std::abs(v));
        }
    }
}

bool GltfAnimationPlayer::animatesCamera(int camera) const {
    for (const PropertyTrack& p : properties_)
        if (p.target.target == camera &&
            (p.target.property == AnimProperty::CameraYfov || p.target.property == AnimProperty::CameraXmag ||
             p.target.property == AnimProperty::CameraYmag))
            return true;
    return false;
}

}  // namespace rf::anim
