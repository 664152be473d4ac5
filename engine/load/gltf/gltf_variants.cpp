#include "engine/load/gltf/gltf_variants.h"

#include "engine/util/errors.h"

namespace rf::gltf {

namespace {

const char* kExtension = "KHR_materials_variants";

/// The integers of an array value (non-integers as −1, so a check refuses them).
std::vector<int> integers(const tinygltf::Value& a) {
    std::vector<int> out;
    if (!a.IsArray()) return out;
    for (size_t i = 0; i < a.ArrayLen(); ++i) out.push_back(a.Get(int(i)).IsInt() ? a.Get(int(i)).Get<int>() : -1);
    return out;
}

int integer(const tinygltf::Value& o, const char* key) {
    return o.IsObject() && o.Has(key) && o.Get(key).IsInt() ? o.Get(key).Get<int>() : -1;
}

/// The primitive's mappings array, or null.
const tinygltf::Value* mappings(const tinygltf::Primitive& p) {
    auto it = p.extensions.find(kExtension);
    if (it == p.extensions.end() || !it->second.Has("mappings") || !it->second.Get("mappings").IsArray()) return nullptr;
    return &it->second.Get("mappings");
}

}  // namespace

std::vector<std::string> materialVariants(const tinygltf::Model& model) {
    std::vector<std::string> names;
    auto it = model.extensions.find(kExtension);
    if (it == model.extensions.end() || !it->second.Has("variants") || !it->second.Get("variants").IsArray()) return names;
    const tinygltf::Value& vs = it->second.Get("variants");
    for (size_t i = 0; i < vs.ArrayLen(); ++i) {
        const tinygltf::Value& v = vs.Get(int(i));
        names.push_back(v.IsObject() && v.Has("name") && v.Get("name").IsString() ? v.Get("name").Get<std::string>() : std::string());
    }
    return names;
}

std::string listVariants(const std::vector<std::string>& names) {
    std::string s = std::to_string(names.size());
    s += ": ";
    for (size_t i = 0; i < names.size(); ++i) {
        if (i) s += ", ";
        s += '"';
        s += names[i];
        s += '"';
    }
    return s;
}

int chooseVariant(const tinygltf::Model& model, const std::string& file, const std::string& name, const std::string& what) {
    const std::vector<std::string> names = materialVariants(model);
    if (names.empty()) throw InputError(file, what + ": the file has no material variants (KHR_materials_variants)");
    int chosen = -1;
    for (size_t i = 0; i < names.size() && chosen < 0; ++i)
        if (names[i] == name) chosen = int(i);
    if (chosen < 0) throw InputError(file, what + ": no variant named \"" + name + "\" (the file has " + listVariants(names) + ")");
    for (size_t m = 0; m < model.meshes.size(); ++m)
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            const tinygltf::Value* maps = mappings(model.meshes[m].primitives[p]);
            if (!maps) continue;
            const std::string w = "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "].extensions." + kExtension;
            for (size_t k = 0; k < maps->ArrayLen(); ++k) {
                const tinygltf::Value& map = maps->Get(int(k));
                const std::string wk = w + ".mappings[" + std::to_string(k) + "]";
                const int material = integer(map, "material");
                if (material < 0 || size_t(material) >= model.materials.size())
                    throw InputError(file, wk + ".material: no material " + std::to_string(material));
                for (int v : integers(map.Get("variants")))
                    if (v < 0 || size_t(v) >= names.size()) throw InputError(file, wk + ".variants: no variant " + std::to_string(v));
            }
        }
    return chosen;
}

int variantMaterial(const tinygltf::Primitive& p, int variant) {
    const tinygltf::Value* maps = mappings(p);
    if (!maps || variant < 0) return p.material;
    for (size_t k = 0; k < maps->ArrayLen(); ++k) {
        const tinygltf::Value& map = maps->Get(int(k));
        for (int v : integers(map.Get("variants")))
            if (v == variant) return integer(map, "material");
    }
    return p.material;
}

}  // namespace rf::gltf
