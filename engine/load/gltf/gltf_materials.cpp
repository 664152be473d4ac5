#include "engine/load/gltf/gltf_materials.h"

#include <cstdio>
#include <limits>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_accessors.h"
#include "engine/load/gltf/gltf_images.h"
#include "engine/load/gltf/gltf_safety.h"
#include "engine/util/image.h"
#include "engine/util/load_control.h"
#include "engine/materials/specular_glossiness.h"

namespace rf::gltf {

namespace {

double number(const tinygltf::Value& v, const char* key, double fallback) {
    if (!v.IsObject() || !v.Has(key)) return fallback;
    const tinygltf::Value& x = v.Get(key);
    if (!x.IsNumber()) return fallback;
    const double d = x.GetNumberAsDouble();
    return std::isfinite(d) ? d : fallback;
}

/// What a number looks like in a message (%g).
std::string shown(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

double element(const tinygltf::Value& arr, int i, double fallback) {
    const tinygltf::Value& x = arr.Get(i);
    if (!x.IsNumber()) return fallback;
    const double d = x.GetNumberAsDouble();
    return std::isfinite(d) ? d : fallback;
}

float clamp01(double x) { return float(std::clamp(std::isfinite(x) ? x : 0.0, 0.0, 1.0)); }

Wrap wrapOf(int glWrap) {
    switch (glWrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Wrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Wrap::MirroredRepeat;
        default: return Wrap::Repeat;
    }
}

}  // namespace

float shininessFromRoughness(float roughness) {
    const float a = std::max(roughness * roughness, 1e-3f);
    return std::clamp(2.f / (a * a) - 2.f, 1.f, 4096.f);
}

MaterialBuilder::MaterialBuilder(Scene& scene, const tinygltf::Model& model, std::string file, const AssetOptions& assets)
    : scene_(scene), model_(model), file_(std::move(file)), assets_(assets) {}

void MaterialBuilder::note(const std::string& text) {
    if (noted_.insert(text).second) scene_.notes.push_back(file_ + ": " + text);
}

int MaterialBuilder::materialFor(int index) {
    if (index >= int(model_.materials.size())) index = -1;  // tinygltf does not check; use the default
    if (auto it = materials_.find(index); it != materials_.end()) return it->second;
    Material m;
    if (index < 0) {
        // glTF's default material: white, metallic 1, roughness 1. A black-background Whitted
        // world would show a fully metallic surface as black, so use the dielectric reading.
        tinygltf::Material def;
        def.pbrMetallicRoughness.metallicFactor = 0.0;
        m = convert(def, "default material");
        m.name = "glTF default";
    } else {
        m = convert(model_.materials[size_t(index)], "materials[" + std::to_string(index) + "]");
    }
    const int id = int(scene_.materials.size());
    scene_.materials.push_back(m);
    materials_[index] = id;
    return id;
}

void MaterialBuilder::readTransform(const tinygltf::ExtensionMap& ext, int texCoord, TextureTransform& t) {
    t.texCoord = texCoord;
    auto it = ext.find("KHR_texture_transform");
    if (it == ext.end()) return;
    const tinygltf::Value& v = it->second;
    auto pair = [&](const char* key, Vec2 fallback) {
        if (!v.Has(key) || !v.Get(key).IsArray() || v.Get(key).ArrayLen() != 2) return fallback;
        return Vec2(float(element(v.Get(key), 0, fallback.x)), float(element(v.Get(key), 1, fallback.y)));
    };
    t.offset = pair("offset", Vec2(0.f));
    t.scale = pair("scale", Vec2(1.f));
    t.rotation = float(number(v, "rotation", 0.0));
    t.texCoord = int(number(v, "texCoord", texCoord));  // the extension's texCoord overrides
}

namespace {

/// glTF's alphaMode: MASK cuts at alphaCutoff; BLEND lays the surface over what is behind it
/// with its alpha (factor × texture × vertex alpha, per hit: gltfCoverage), without bending.
void applyAlphaMode(const tinygltf::Material& gm, Material& m) {
    if (gm.alphaMode == "MASK") {
        m.alphaMode = AlphaMode::Mask;
        m.alphaCutoff = float(std::isfinite(gm.alphaCutoff) ? gm.alphaCutoff : 0.5);
    } else if (gm.alphaMode == "BLEND") {
        m.alphaMode = AlphaMode::Blend;
    }
}

}  // namespace

double MaterialBuilder::checkedIor(const tinygltf::Value& ext, const std::string& where, const std::string& name) const {
    const double ior = number(ext, "ior", 1.5);
    // KHR_materials_ior's schema: 1 or more, or exactly 0; an IOR below 1 would be refused by a
    // scene file ("ior": expected a positive number) and is no medium a model describes.
    if (!(ior >= 1.0 || ior == 0.0))
        throw InputError(file_, where + (name.empty() ? "" : " (\"" + name + "\")") + ".extensions.KHR_materials_ior.ior " + shown(ior) +
                                    ": expected an index of refraction of 1 or more (or 0)");
    return ior;
}

Material MaterialBuilder::convert(const tinygltf::Material& gm, const std::string& where) {
    Material m;
    m.name = gm.name;
    const auto& pbr = gm.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4) {
        m.color = Color(clamp01(pbr.baseColorFactor[0]), clamp01(pbr.baseColorFactor[1]), clamp01(pbr.baseColorFactor[2]));
        m.alpha = clamp01(pbr.baseColorFactor[3]);
    }
    const float metallic = clamp01(pbr.metallicFactor), roughness = clamp01(pbr.roughnessFactor);
    // The glTF BRDF shades it (material_gltf.h); the tracer's own mirror weight stays 0, as the
    // glTF model traces its reflections itself, weighted by Fresnel.
    m.gltfPbr = true;
    m.metallic = metallic;
    m.roughness = roughness;
    m.reflection = 0.f;
    m.doubleSided = gm.doubleSided;
    if (pbr.metallicRoughnessTexture.index >= 0) {
        m.metallicRoughnessTexture = textureFor(pbr.metallicRoughnessTexture.index, false, where + ".metallicRoughnessTexture");
        readTransform(pbr.metallicRoughnessTexture.extensions, pbr.metallicRoughnessTexture.texCoord, m.metallicRoughnessTransform);
    }

    if (pbr.baseColorTexture.index >= 0) {
        m.baseColorTexture = textureFor(pbr.baseColorTexture.index, true, where + ".baseColorTexture");
        readTransform(pbr.baseColorTexture.extensions, pbr.baseColorTexture.texCoord, m.baseColorTransform);
    }
    if (gm.normalTexture.index >= 0) {
        m.normalTexture = textureFor(gm.normalTexture.index, false, where + ".normalTexture");
        m.normalScale = float(std::isfinite(gm.normalTexture.scale) ? gm.normalTexture.scale : 1.0);
        readTransform(gm.normalTexture.extensions, gm.normalTexture.texCoord, m.normalTransform);
    }
    if (gm.emissiveTexture.index >= 0) {
        m.emissiveTexture = textureFor(gm.emissiveTexture.index, true, where + ".emissiveTexture");
        readTransform(gm.emissiveTexture.extensions, gm.emissiveTexture.texCoord, m.emissiveTransform);
    }
    if (gm.occlusionTexture.index >= 0) {
        m.occlusionTexture = textureFor(gm.occlusionTexture.index, false, where + ".occlusionTexture");
        m.occlusionStrength = clamp01(gm.occlusionTexture.strength);
        readTransform(gm.occlusionTexture.extensions, gm.occlusionTexture.texCoord, m.occlusionTransform);
    }

    float emissiveStrength = 1.f;
    float transmission = 0.f;
    for (const auto& [name, value] : gm.extensions) {
        if (name == "KHR_materials_emissive_strength") emissiveStrength = float(std::max(0.0, number(value, "emissiveStrength", 1.0)));
        else if (name == "KHR_materials_transmission") transmission = clamp01(number(value, "transmissionFactor", 0.0));
        else if (name == "KHR_materials_ior") m.ior = float(std::clamp(checkedIor(value, where, gm.name), 1.0, 10.0));
        else if (name == "KHR_materials_specular") m.specularWeight = clamp01(number(value, "specularFactor", 1.0));
        else if (name == "KHR_materials_unlit") m.unlit = true;
        else if (name == "KHR_materials_clearcoat") readClearcoat(value, m, where + ".extensions.KHR_materials_clearcoat");
        else if (name == "KHR_materials_sheen") readSheen(value, m, where + ".extensions.KHR_materials_sheen");
        else if (name == "KHR_materials_iridescence") readIridescence(value, m, where + (gm.name.empty() ? "" : " (\"" + gm.name + "\")") +
                                                                                 ".extensions.KHR_materials_iridescence");
        else if (name == "KHR_materials_dispersion") {
            const double d = number(value, "dispersion", 0.0);
            if (!(d >= 0.0))
                throw InputError(file_, where + (gm.name.empty() ? "" : " (\"" + gm.name + "\")") +
                                            ".extensions.KHR_materials_dispersion.dispersion " + shown(d) +
                                            ": expected a dispersion (20 / Abbe number) of 0 or more");
            m.dispersion = float(std::min(d, 100.0));
        }
        else if (name == "KHR_materials_volume") readVolume(value, m, where + ".extensions.KHR_materials_volume");
        else if (name == "KHR_materials_pbrSpecularGlossiness") readSpecularGlossiness(value, m, where + ".extensions." + name);
        else if (!isSupportedExtension(name)) note("material extension " + name + " ignored");
    }
    if (gm.emissiveFactor.size() == 3)
        m.emission = emissiveStrength * Color(clamp01(gm.emissiveFactor[0]), clamp01(gm.emissiveFactor[1]), clamp01(gm.emissiveFactor[2]));

    if (transmission > 0.f) {
        // Refraction through the base colour; the surface's own shading fades accordingly.
        m.transmission = transmission;
        m.diffuse *= 1.f - transmission;
    }
    applyAlphaMode(gm, m);
    return m;
}

/// A textureInfo object inside an extension (tinygltf leaves those as plain values).
void MaterialBuilder::extensionTexture(const tinygltf::Value& ext, const char* key, const std::string& where, bool srgb,
                                       int& texture, TextureTransform& transform, float* scale) {
    if (!ext.Has(key) || !ext.Get(key).IsObject()) return;
    const tinygltf::Value& info = ext.Get(key);
    const int index = int(number(info, "index", -1.0));
    if (index < 0) return;
    texture = textureFor(index, srgb, where + "." + key);
    tinygltf::ExtensionMap ext2;
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
        const tinygltf::Value& e = info.Get("extensions");
        for (const std::string& k : e.Keys()) ext2[k] = e.Get(k);
    }
    readTransform(ext2, int(number(info, "texCoord", 0.0)), transform);
    if (scale) *scale = float(number(info, "scale", 1.0));
}

/// KHR_materials_pbrSpecularGlossiness in place of pbrMetallicRoughness (specular_glossiness.h):
/// the factors converted here; with a diffuse or specular-glossiness texture the material keeps
/// the factors and textures, the diffuse ones as its base colour, and is converted at every
/// shading point (material_gltf.cpp), texel by texel.
void MaterialBuilder::readSpecularGlossiness(const tinygltf::Value& v, Material& m, const std::string& where) {
    auto vec = [&](const char* key, int n, float fallback, float out[4]) {
        for (int i = 0; i < n; ++i) out[i] = fallback;
        if (!v.Has(key) || !v.Get(key).IsArray() || int(v.Get(key).ArrayLen()) != n) return;
        for (int i = 0; i < n; ++i) out[i] = clamp01(element(v.Get(key), i, fallback));
    };
    float diffuse[4], specular[4];
    vec("diffuseFactor", 4, 1.f, diffuse);
    vec("specularFactor", 3, 1.f, specular);
    const float glossiness = clamp01(number(v, "glossinessFactor", 1.0));
    const Color d(diffuse[0], diffuse[1], diffuse[2]), s(specular[0], specular[1], specular[2]);
    const SpecularGlossinessAsMetallic mr = convertSpecularGlossiness(d, s, glossiness);
    m.color = mr.baseColor;
    m.alpha = diffuse[3];
    m.metallic = mr.metallic;
    m.roughness = mr.roughness;
    m.metallicRoughnessTexture = -1;
    m.baseColorTexture = -1;
    extensionTexture(v, "diffuseTexture", where, true, m.baseColorTexture, m.baseColorTransform, nullptr);
    // RGB is the specular colour in sRGB, A the glossiness (linear): decoded as an sRGB texture.
    extensionTexture(v, "specularGlossinessTexture", where, true, m.specularGlossinessTexture, m.specularGlossinessTransform,
                     nullptr);
    if (m.baseColorTexture >= 0 || m.specularGlossinessTexture >= 0) {
        m.specularGlossiness = true;
        m.color = d;  // baseColor() then gives the diffuse colour, which the conversion takes
        m.sgSpecular = s;
        m.sgGlossiness = glossiness;
    }
}

void MaterialBuilder::readClearcoat(const tinygltf::Value& v, Material& m, const std::string& where) {
    m.clearcoat = clamp01(number(v, "clearcoatFactor", 0.0));
    m.clearcoatRoughness = clamp01(number(v, "clearcoatRoughnessFactor", 0.0));
    if (m.clearcoat <= 0.f) return;  // no coat: its textures are never decoded
    extensionTexture(v, "clearcoatTexture", where, false, m.clearcoatTexture, m.clearcoatTransform, nullptr);
    extensionTexture(v, "clearcoatRoughnessTexture", where, false, m.clearcoatRoughnessTexture, m.clearcoatRoughnessTransform, nullptr);
    extensionTexture(v, "clearcoatNormalTexture", where, false, m.clearcoatNormalTexture, m.clearcoatNormalTransform,
                     &m.clearcoatNormalScale);
}

void MaterialBuilder::readSheen(const tinygltf::Value& v, Material& m, const std::string& where) {
    if (v.Has("sheenColorFactor") && v.Get("sheenColorFactor").IsArray() && v.Get("sheenColorFactor").ArrayLen() == 3) {
        const tinygltf::Value& c = v.Get("sheenColorFactor");
        m.sheenColor = Color(clamp01(element(c, 0, 0.0)), clamp01(element(c, 1, 0.0)), clamp01(element(c, 2, 0.0)));
    }
    m.sheenRoughness = clamp01(number(v, "sheenRoughnessFactor", 0.0));
    if (m.sheenColor == Color(0.f)) return;  // "If sheenColorFactor is zero, the whole sheen layer is disabled"
    extensionTexture(v, "sheenColorTexture", where, true, m.sheenColorTexture, m.sheenColorTransform, nullptr);
    extensionTexture(v, "sheenRoughnessTexture", where, false, m.sheenRoughnessTexture, m.sheenRoughnessTransform, nullptr);
}

/// KHR_materials_iridescence. The schema's bounds refused as KHR_materials_ior's are (exit 2,
/// naming the material and the value): an index below 1, a negative thickness.
void MaterialBuilder::readIridescence(const tinygltf::Value& v, Material& m, const std::string& where) {
    m.iridescence = clamp01(number(v, "iridescenceFactor", 0.0));
    const double ior = number(v, "iridescenceIor", 1.3);
    if (!(ior >= 1.0))
        throw InputError(file_, where + ".iridescenceIor " + shown(ior) + ": expected an index of refraction of 1 or more");
    m.iridescenceIor = float(std::min(ior, 10.0));
    auto thickness = [&](const char* key, double fallback) {
        const double t = number(v, key, fallback);
        if (!(t >= 0.0))
            throw InputError(file_, where + "." + key + " " + shown(t) + ": expected a thickness of 0 nm or more");
        return float(std::min(t, 1e6));
    };
    m.iridescenceThicknessMin = thickness("iridescenceThicknessMinimum", 100.0);
    m.iridescenceThicknessMax = thickness("iridescenceThicknessMaximum", 400.0);
    if (m.iridescence <= 0.f) return;  // no film: its textures are never decoded
    extensionTexture(v, "iridescenceTexture", where, false, m.iridescenceTexture, m.iridescenceTransform, nullptr);
    extensionTexture(v, "iridescenceThicknessTexture", where, false, m.iridescenceThicknessTexture,
                     m.iridescenceThicknessTransform, nullptr);
}

void MaterialBuilder::readVolume(const tinygltf::Value& v, Material& m, const std::string& where) {
    m.thickness = float(std::max(0.0, number(v, "thicknessFactor", 0.0)));
    const double distance = number(v, "attenuationDistance", std::numeric_limits<double>::infinity());
    Color color(1.f);
    if (v.Has("attenuationColor") && v.Get("attenuationColor").IsArray() && v.Get("attenuationColor").ArrayLen() == 3) {
        const tinygltf::Value& c = v.Get("attenuationColor");
        color = Color(clamp01(element(c, 0, 1.0)), clamp01(element(c, 1, 1.0)), clamp01(element(c, 2, 1.0)));
    }
    m.attenuation = volumeAbsorption(color, distance);
    if (m.thickness <= 0.f) return;  // thin-walled: no volume, and its texture is never decoded
    extensionTexture(v, "thicknessTexture", where, false, m.thicknessTexture, m.thicknessTransform, nullptr);
}

int MaterialBuilder::textureFor(int index, bool srgb, const std::string& where) {
    if (index < 0 || size_t(index) >= model_.textures.size()) {
        note(where + ": no texture " + std::to_string(index) + ", ignored");
        return -1;
    }
    const tinygltf::Texture& gt = model_.textures[size_t(index)];
    const int image = imageOf(gt, index, where);
    const int sampler = (gt.sampler >= 0 && size_t(gt.sampler) < model_.samplers.size()) ? gt.sampler : -1;
    if (image < 0) return -1;
    const auto key = std::make_tuple(image, sampler, srgb);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    textures_[key] = -1;

    std::optional<Texture> t = decodeImage(image, srgb, where);
    if (!t) return -1;
    ++decodedImages_;
    if (sampler >= 0) {
        const tinygltf::Sampler& s = model_.samplers[size_t(sampler)];
        t->wrapS = wrapOf(s.wrapS);
        t->wrapT = wrapOf(s.wrapT);
        t->filter = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST ? Filter::Nearest : Filter::Linear;
    }
    buildMipmaps(*t);
    const int id = int(scene_.textures.size());
    scene_.textures.push_back(std::move(*t));
    textures_[key] = id;
    return id;
}

std::optional<ByteSpan> MaterialBuilder::encodedImage(int image, const std::string& wi) {
    const tinygltf::Image& gi = model_.images[size_t(image)];
    try {
        if (gi.bufferView >= 0) return bufferViewSpan(model_, gi.bufferView, file_);
        if (gi.width == -1) return ByteSpan{gi.image.data(), gi.image.size()};  // kept encoded by the loader
    } catch (const std::exception& e) {
        note(wi + ": " + e.what() + "; texture ignored");
        return std::nullopt;
    }
    return ByteSpan{};
}

int MaterialBuilder::imageOf(const tinygltf::Texture& gt, int index, const std::string& where) {
    const std::string wt = "textures[" + std::to_string(index) + "]";
    auto extensionSource = [&](const char* name) {
        auto it = gt.extensions.find(name);
        if (it == gt.extensions.end() || !it->second.Has("source") || !it->second.Get("source").IsInt()) return -1;
        return it->second.Get("source").Get<int>();
    };
    auto usable = [&](int i) { return i >= 0 && size_t(i) < model_.images.size(); };
    const int webp = extensionSource("EXT_texture_webp");
    if (usable(webp)) return webp;
    if (webp >= 0) note(wt + ".extensions.EXT_texture_webp.source: no image " + std::to_string(webp) + "; its fallback used");
    const bool basisu = gt.extensions.count("KHR_texture_basisu") != 0;
    if (basisu && !usable(gt.source))
        throw InputError(file_, wt + " has only a KTX2 (KHR_texture_basisu) image, which rayfarm cannot decode (Debian has no "
                                     "Basis Universal decoder); the file needs a PNG, JPEG or WebP fallback in the texture's "
                                     "\"source\" (e.g. gltf-transform or gltfpack without -tc)");
    if (!usable(gt.source)) {
        note(where + ": texture without a usable image, ignored");
        return -1;
    }
    return gt.source;
}

std::optional<Texture> MaterialBuilder::decodeImage(int image, bool srgb, const std::string& where) {
    LoadStep step("decoding its textures");
    pollLoadCancel();
    const tinygltf::Image& gi = model_.images[size_t(image)];
    const std::string mime = dataUriMime(gi.uri);
    const std::string wi = "images[" + std::to_string(image) + "]" +
                           (gi.uri.empty() ? std::string() : mime.empty() ? " \"" + gi.uri + "\"" : " (data URI of type " + mime + ")");
    const auto enc = encodedImage(image, wi);
    if (!enc) return std::nullopt;
    const unsigned char* bytes = enc->data;
    const size_t size = enc->size;
    ImageHeader header;
    std::string why;
    if (!bytes || size == 0) {
        note(wi + ": image missing; texture ignored");
        return std::nullopt;
    }
    if (size > Limits::kMaxImageBytes || !readImageHeader(bytes, size, header, why)) {
        if (header.format == ImageFormat::Ktx2)
            throw InputError(file_, where + ": " + wi + " is " + why + "; the file needs a PNG, JPEG or WebP image here");
        note(wi + ": image not decodable (" + (why.empty() ? "over the size limit" : why) + "); texture ignored");
        return std::nullopt;
    }
    const int w = header.width, h = header.height;
    if (w <= 0 || h <= 0 || w > Limits::kMaxImageSide || h > Limits::kMaxImageSide) {
        note(wi + ": image of " + std::to_string(w) + "x" + std::to_string(h) + " is over the size limit; texture ignored");
        return std::nullopt;
    }
    // The budget, from the header: float RGBA texels and a third more for the mip-maps.
    const int k = downsampleFactor(w, h, assets_.maxTextureSize);
    const uint64_t dw = uint64_t((w + k - 1) / k), dh = uint64_t((h + k - 1) / k);
    const uint64_t cost = dw * dh * sizeof(Vec4) * 4 / 3;
    uint64_t used = 0;
    for (const Texture& t : scene_.textures) {
        used += t.texels.size() * sizeof(Vec4);
        for (const TextureLevel& l : t.mips) used += l.texels.size() * sizeof(Vec4);
    }
    if (used + cost > assets_.textureBudgetBytes)
        throw InputError(file_, wi + ": its " + std::to_string(dw) + "x" + std::to_string(dh) + " texels (" +
                                    std::to_string(cost >> 20) + " MB with mip-maps) would take the textures to " +
                                    std::to_string((used + cost) >> 20) + " MB, over the budget of " +
                                    std::to_string(assets_.textureBudgetBytes >> 20) +
                                    " MB; lower --max-texture-size (now " + std::to_string(assets_.maxTextureSize) + ")");
    std::optional<Rgba8Image> px = gltf::decodeImage(bytes, size, assets_.maxTextureSize, why);
    if (!px) {
        note(wi + ": cannot decode " + formatName(header.format) + " image (" + why + "); texture ignored");
        return std::nullopt;
    }
    if (px->width != w || px->height != h)
        note(wi + ": " + std::to_string(w) + "x" + std::to_string(h) + " downsampled to " + std::to_string(px->width) + "x" +
             std::to_string(px->height) + " on load (--max-texture-size " + std::to_string(assets_.maxTextureSize) + ")");
    Texture t;
    t.width = px->width;
    t.height = px->height;
    // Base colour is sRGB-encoded; normal maps are linear data. Alpha is always linear.
    float lut[256];
    for (int i = 0; i < 256; ++i) lut[i] = srgb ? srgbDecode(i / 255.f) : i / 255.f;
    const uint8_t* p = px->pixels.data();
    // Appended, not resized and overwritten: zeroing an 8192² float texture first cost more
    // than decoding the image.
    const size_t n = size_t(t.width) * t.height;
    t.texels.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        if (i % (1 << 20) == 0) pollLoadCancel();
        t.texels.emplace_back(lut[p[4 * i]], lut[p[4 * i + 1]], lut[p[4 * i + 2]], p[4 * i + 3] / 255.f);
    }
    return t;
}

}  // namespace rf::gltf
