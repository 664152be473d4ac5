#pragma once
/// glTF metallic-roughness materials mapped onto the engine's Phong/Whitted material, and
/// textures decoded lazily: only images that a material some drawn primitive uses are decoded.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>

#include <tiny_gltf.h>

#include "engine/load/gltf/gltf_accessors.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_options.h"

namespace rf::gltf {

/// Converts glTF materials on first use and appends them (and their textures) to a scene.
class MaterialBuilder {
public:
    MaterialBuilder(Scene& scene, const tinygltf::Model& model, std::string file, const AssetOptions& assets = {});

    /// Scene material index for glTF material `index` (−1: the glTF default material).
    int materialFor(int index);
    /// Scene material index of glTF material `index` if some primitive used it, else −1.
    int converted(int index) const {
        auto it = materials_.find(index);
        return it == materials_.end() ? -1 : it->second;
    }

    /// Number of images decoded so far (for tests: untextured models decode none).
    int decodedImages() const { return decodedImages_; }

private:
    Material convert(const tinygltf::Material& gm, const std::string& where);
    /// Scene texture for glTF texture `index`, decoded on first use; −1 if it cannot be used.
    int textureFor(int index, bool srgb, const std::string& where);
    /// The image's encoded bytes (a bufferView, or kept encoded by the loader); {nullptr, 0} when
    /// it has none, nullopt (with a note) when its bufferView is unusable.
    std::optional<ByteSpan> encodedImage(int image, const std::string& wi);
    /// The image decoded to linear RGBA texels; nullopt, with a note, when it cannot be used.
    /// Throws InputError when it would take the scene's textures past the budget.
    std::optional<Texture> decodeImage(int image, bool srgb, const std::string& where);
    /// The image a texture draws: EXT_texture_webp's source, else its own source (the fallback
    /// of KHR_texture_basisu); −1 with a note when there is none. Throws InputError for a
    /// KTX2-only texture, which rayfarm cannot decode.
    int imageOf(const tinygltf::Texture& t, int index, const std::string& where);
    void readTransform(const tinygltf::ExtensionMap& ext, int texCoord, TextureTransform& t);
    void extensionTexture(const tinygltf::Value& ext, const char* key, const std::string& where, bool srgb, int& texture,
                          TextureTransform& transform, float* scale);
    /// KHR_materials_clearcoat: factors, and the coat's weight, roughness and normal textures.
    void readClearcoat(const tinygltf::Value& v, Material& m, const std::string& where);
    void readSheen(const tinygltf::Value& v, Material& m, const std::string& where);
    void readIridescence(const tinygltf::Value& v, Material& m, const std::string& where);
    void readVolume(const tinygltf::Value& v, Material& m, const std::string& where);
    void readSpecularGlossiness(const tinygltf::Value& v, Material& m, const std::string& where);
    /// KHR_materials_ior's ior (1.5 when absent); throws InputError naming the material (where,
    /// and its name) and the value when it is below 1 and not 0.
    double checkedIor(const tinygltf::Value& ext, const std::string& where, const std::string& name) const;
    void note(const std::string& text);

    Scene& scene_;
    const tinygltf::Model& model_;
    std::string file_;
    AssetOptions assets_;
    std::map<int, int> materials_;
    std::map<std::tuple<int, int, bool>, int> textures_;  ///< (image, sampler, sRGB) → scene texture
    std::set<std::string> noted_;
    int decodedImages_ = 0;
};

/// Phong exponent that gives roughly the highlight of a GGX lobe with this perceptual roughness
/// (Blinn-Phong ↔ Beckmann: n = 2/α² − 2, α = roughness²), clamped to [1, 4096].
float shininessFromRoughness(float roughness);

}  // namespace rf::gltf
