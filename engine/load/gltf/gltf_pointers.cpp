// KHR_animation_pointer: what a channel's JSON pointer names, resolved against the file. Node
// transforms and weights become plain channels; the light, camera, material, texture-transform
// and visibility properties rayfarm draws become PropertyChannels; anything else is left out
// with a note. A pointer at something the file lacks is refused naming both.
#include <map>

#include "engine/load/gltf/gltf_model.h"
#include "engine/util/errors.h"

namespace rf::gltf {

namespace {

bool isIndex(const std::string& x) { return !x.empty() && x.size() < 10 && x.find_first_not_of("0123456789") == std::string::npos; }

/// The path inside a material (after /materials/N/) of each texture slot's textureInfo.
const std::map<std::string, TextureSlot>& textureSlots() {
    static const std::map<std::string, TextureSlot> slots = {
        {"pbrMetallicRoughness/baseColorTexture", TextureSlot::BaseColor},
        {"pbrMetallicRoughness/metallicRoughnessTexture", TextureSlot::MetallicRoughness},
        {"normalTexture", TextureSlot::Normal},
        {"occlusionTexture", TextureSlot::Occlusion},
        {"emissiveTexture", TextureSlot::Emissive},
        {"extensions/KHR_materials_clearcoat/clearcoatTexture", TextureSlot::Clearcoat},
        {"extensions/KHR_materials_clearcoat/clearcoatRoughnessTexture", TextureSlot::ClearcoatRoughness},
        {"extensions/KHR_materials_clearcoat/clearcoatNormalTexture", TextureSlot::ClearcoatNormal},
        {"extensions/KHR_materials_sheen/sheenColorTexture", TextureSlot::SheenColor},
        {"extensions/KHR_materials_sheen/sheenRoughnessTexture", TextureSlot::SheenRoughness},
        {"extensions/KHR_materials_volume/thicknessTexture", TextureSlot::Thickness},
        {"extensions/KHR_materials_iridescence/iridescenceTexture", TextureSlot::Iridescence},
        {"extensions/KHR_materials_iridescence/iridescenceThicknessTexture", TextureSlot::IridescenceThickness},
    };
    return slots;
}

/// The material properties (after /materials/N/) rayfarm animates.
const std::map<std::string, AnimProperty>& materialProperties() {
    static const std::map<std::string, AnimProperty> props = {
        {"pbrMetallicRoughness/baseColorFactor", AnimProperty::BaseColor},
        {"pbrMetallicRoughness/metallicFactor", AnimProperty::Metallic},
        {"pbrMetallicRoughness/roughnessFactor", AnimProperty::Roughness},
        {"emissiveFactor", AnimProperty::Emissive},
        {"alphaCutoff", AnimProperty::AlphaCutoff},
        {"normalTexture/scale", AnimProperty::NormalScale},
        {"occlusionTexture/strength", AnimProperty::OcclusionStrength},
        {"extensions/KHR_materials_emissive_strength/emissiveStrength", AnimProperty::EmissiveStrength},
        {"extensions/KHR_materials_transmission/transmissionFactor", AnimProperty::Transmission},
        {"extensions/KHR_materials_ior/ior", AnimProperty::Ior},
        {"extensions/KHR_materials_volume/thicknessFactor", AnimProperty::Thickness},
        {"extensions/KHR_materials_volume/attenuationColor", AnimProperty::AttenuationColor},
        {"extensions/KHR_materials_volume/attenuationDistance", AnimProperty::AttenuationDistance},
        {"extensions/KHR_materials_clearcoat/clearcoatFactor", AnimProperty::Clearcoat},
        {"extensions/KHR_materials_clearcoat/clearcoatRoughnessFactor", AnimProperty::ClearcoatRoughness},
        {"extensions/KHR_materials_clearcoat/clearcoatNormalTexture/scale", AnimProperty::ClearcoatNormalScale},
        {"extensions/KHR_materials_sheen/sheenColorFactor", AnimProperty::SheenColor},
        {"extensions/KHR_materials_sheen/sheenRoughnessFactor", AnimProperty::SheenRoughness},
        {"extensions/KHR_materials_specular/specularFactor", AnimProperty::Specular},
        {"extensions/KHR_materials_iridescence/iridescenceFactor", AnimProperty::Iridescence},
        {"extensions/KHR_materials_iridescence/iridescenceIor", AnimProperty::IridescenceIor},
        {"extensions/KHR_materials_iridescence/iridescenceThicknessMinimum", AnimProperty::IridescenceThicknessMin},
        {"extensions/KHR_materials_iridescence/iridescenceThicknessMaximum", AnimProperty::IridescenceThicknessMax},
    };
    return props;
}

/// Whether material gm has a texture in slot (its textureInfo is present).
bool hasTexture(const tinygltf::Material& gm, TextureSlot slot) {
    auto inExtension = [&](const char* ext, const char* key) {
        auto it = gm.extensions.find(ext);
        return it != gm.extensions.end() && it->second.Has(key) && it->second.Get(key).IsObject();
    };
    switch (slot) {
        case TextureSlot::BaseColor: return gm.pbrMetallicRoughness.baseColorTexture.index >= 0;
        case TextureSlot::MetallicRoughness: return gm.pbrMetallicRoughness.metallicRoughnessTexture.index >= 0;
        case TextureSlot::Normal: return gm.normalTexture.index >= 0;
        case TextureSlot::Occlusion: return gm.occlusionTexture.index >= 0;
        case TextureSlot::Emissive: return gm.emissiveTexture.index >= 0;
        case TextureSlot::Clearcoat: return inExtension("KHR_materials_clearcoat", "clearcoatTexture");
        case TextureSlot::ClearcoatRoughness: return inExtension("KHR_materials_clearcoat", "clearcoatRoughnessTexture");
        case TextureSlot::ClearcoatNormal: return inExtension("KHR_materials_clearcoat", "clearcoatNormalTexture");
        case TextureSlot::SheenColor: return inExtension("KHR_materials_sheen", "sheenColorTexture");
        case TextureSlot::SheenRoughness: return inExtension("KHR_materials_sheen", "sheenRoughnessTexture");
        case TextureSlot::Thickness: return inExtension("KHR_materials_volume", "thicknessTexture");
        case TextureSlot::Iridescence: return inExtension("KHR_materials_iridescence", "iridescenceTexture");
        case TextureSlot::IridescenceThickness: return inExtension("KHR_materials_iridescence", "iridescenceThicknessTexture");
        case TextureSlot::None: break;
    }
    return false;
}

/// parts[from..] joined with '/'.
std::string joined(const std::vector<std::string>& parts, size_t from) {
    std::string s;
    for (size_t i = from; i < parts.size(); ++i) s += (s.empty() ? "" : "/") + parts[i];
    return s;
}

}  // namespace

GltfModel::AnimationPointer GltfModel::animationPointer(const tinygltf::AnimationChannel& ch, const std::string& where,
                                                        int nodes) const {
    const std::string w = where + ".target.extensions.KHR_animation_pointer.pointer";
    auto ext = ch.target_extensions.find("KHR_animation_pointer");
    if (ext == ch.target_extensions.end() || !ext->second.Has("pointer") || !ext->second.Get("pointer").IsString())
        throw InputError(path_, w + ": missing (a \"pointer\" path needs the JSON pointer it animates)");
    const std::string ptr = ext->second.Get("pointer").Get<std::string>();
    AnimationPointer out;
    out.pointer = ptr;
    // The pattern names the kind of target, its indices as {}: "/materials/{}/pbrMetallicRoughness/baseColorFactor".
    std::vector<std::string> parts;
    for (size_t at = 0; at < ptr.size();) {
        if (ptr[at] != '/') throw InputError(path_, w + ": \"" + ptr + "\" is not a JSON pointer (it must start with /)");
        const size_t next = ptr.find('/', at + 1);
        parts.push_back(ptr.substr(at + 1, next == std::string::npos ? std::string::npos : next - at - 1));
        at = next == std::string::npos ? ptr.size() : next;
    }
    for (const std::string& p : parts) out.pattern += "/" + (isIndex(p) ? std::string("{}") : p);
    // A pointer into a list the file does not have that many of points at nothing: refused.
    auto check = [&](size_t at, const char* what, size_t count) {
        if (parts.size() > at && isIndex(parts[at]) && std::stoul(parts[at]) >= count)
            throw InputError(path_, w + ": \"" + ptr + "\" names " + what + " " + parts[at] + ", and the file has " + std::to_string(count));
    };
    auto refuse = [&](const std::string& why) { throw InputError(path_, w + ": \"" + ptr + "\" " + why); };
    auto property = [&](AnimProperty p, int target, TextureSlot slot = TextureSlot::None) {
        PropertyChannel pc;
        pc.sampler = ch.sampler;
        pc.property = p;
        pc.target = target;
        pc.slot = slot;
        out.target = pc;
    };
    if (parts.empty()) return out;
    const std::string& list = parts[0];
    const bool lightList = list == "extensions" && parts.size() > 2 && parts[1] == "KHR_lights_punctual" && parts[2] == "lights";
    if (list == "nodes") check(1, "node", size_t(nodes));
    else if (list == "materials") check(1, "material", model_.materials.size());
    else if (list == "meshes") check(1, "mesh", model_.meshes.size());
    else if (list == "cameras") check(1, "camera", model_.cameras.size());
    else if (lightList) check(3, "light", model_.lights.size());

    if (list == "nodes" && parts.size() >= 3 && isIndex(parts[1])) {
        const int node = std::stoi(parts[1]);
        const std::string rest = joined(parts, 2);
        if (rest == "translation" || rest == "rotation" || rest == "scale" || rest == "weights") {
            out.node = node;
            out.property = rest;
        } else if (rest == "extensions/KHR_node_visibility/visible") {
            property(AnimProperty::NodeVisible, node);
        }
    } else if (lightList && parts.size() >= 5 && isIndex(parts[3])) {
        const int light = std::stoi(parts[3]);
        const std::string rest = joined(parts, 4);
        const bool spot = model_.lights[size_t(light)].type == "spot";
        if (rest == "color") property(AnimProperty::LightColor, light);
        else if (rest == "intensity") property(AnimProperty::LightIntensity, light);
        else if (rest == "range") property(AnimProperty::LightRange, light);
        else if (rest == "spot/innerConeAngle" || rest == "spot/outerConeAngle") {
            if (!spot) refuse("names a spot cone of light " + parts[3] + ", which is a " + model_.lights[size_t(light)].type + " light");
            property(rest == "spot/innerConeAngle" ? AnimProperty::LightSpotInner : AnimProperty::LightSpotOuter, light);
        }
    } else if (list == "cameras" && parts.size() == 4 && isIndex(parts[1])) {
        const int camera = std::stoi(parts[1]);
        const std::string& type = model_.cameras[size_t(camera)].type;
        if (parts[2] != "perspective" && parts[2] != "orthographic") return out;
        if (parts[2] != type) refuse("names the " + parts[2] + " projection of camera " + parts[1] + ", which is " + type);
        if (parts[3] == "yfov") property(AnimProperty::CameraYfov, camera);
        else if (parts[3] == "xmag") property(AnimProperty::CameraXmag, camera);
        else if (parts[3] == "ymag") property(AnimProperty::CameraYmag, camera);
    } else if (list == "materials" && parts.size() >= 3 && isIndex(parts[1])) {
        const int material = std::stoi(parts[1]);
        const std::string rest = joined(parts, 2);
        if (auto it = materialProperties().find(rest); it != materialProperties().end()) {
            property(it->second, material);
        } else if (const size_t cut = rest.rfind("/extensions/KHR_texture_transform/"); cut != std::string::npos) {
            const std::string field = rest.substr(cut + std::string("/extensions/KHR_texture_transform/").size());
            auto slot = textureSlots().find(rest.substr(0, cut));
            if (slot == textureSlots().end() || (field != "offset" && field != "rotation" && field != "scale")) return out;
            if (!hasTexture(model_.materials[size_t(material)], slot->second))
                refuse("names a texture transform of material " + parts[1] + "'s " + slot->first + ", which the material lacks");
            property(field == "offset" ? AnimProperty::TextureOffset : field == "rotation" ? AnimProperty::TextureRotation
                                                                                          : AnimProperty::TextureScale,
                     material, slot->second);
        }
    }
    return out;
}

}  // namespace rf::gltf
