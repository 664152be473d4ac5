#include "engine/load/assimp/assimp_textures.h"

#include <algorithm>
#include <cstdint>

#include "engine/load/gltf/gltf_images.h"
#include "engine/util/image.h"

namespace rf {

namespace {

/// The largest side a combined map keeps (the glTF loader's default --max-texture-size).
constexpr int kMaxSide = 8192;

/// The map decoded, or nullopt with why set to what (a literal: a message built from pieces
/// here, in a function GCC 12 clones, trips its link-time -Wstringop-overflow false positive).
std::optional<gltf::Rgba8Image> decode(const std::vector<unsigned char>& bytes, const char* what, std::string& why) {
    std::string ignored;
    auto img = gltf::decodeImage(bytes.data(), bytes.size(), kMaxSide, ignored);
    if (!img) why = what;
    return img;
}

/// The texel of img nearest to (x, y) of a w × h grid.
const uint8_t* nearest(const gltf::Rgba8Image& img, int x, int y, int w, int h) {
    const int sx = std::min(img.width - 1, int((int64_t(x) * img.width + img.width / 2) / w));
    const int sy = std::min(img.height - 1, int((int64_t(y) * img.height + img.height / 2) / h));
    return &img.pixels[(size_t(sy) * size_t(img.width) + size_t(sx)) * 4];
}

uint8_t luminance(const uint8_t* p) { return uint8_t((2126u * p[0] + 7152u * p[1] + 722u * p[2] + 5000u) / 10000u); }

std::optional<std::vector<unsigned char>> png(int w, int h, const std::vector<uint8_t>& rgba, std::string& why) {
    const std::string bytes = encodePng(w, h, rgba, 4);
    if (bytes.empty()) return why = "could not encode the combined map", std::nullopt;
    return std::vector<unsigned char>(bytes.begin(), bytes.end());
}

}  // namespace

std::optional<std::vector<unsigned char>> withOpacityMap(const std::vector<unsigned char>& colour, const std::vector<unsigned char>& opacity,
                                                         std::string& why) {
    const auto a = decode(opacity, "the opacity map cannot be decoded", why);
    if (!a) return std::nullopt;
    std::optional<gltf::Rgba8Image> c;
    if (!colour.empty() && !(c = decode(colour, "the base colour texture cannot be decoded", why))) return std::nullopt;
    const int w = c ? std::max(c->width, a->width) : a->width, h = c ? std::max(c->height, a->height) : a->height;
    std::vector<uint8_t> out(size_t(w) * size_t(h) * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* o = &out[(size_t(y) * size_t(w) + size_t(x)) * 4];
            if (c) std::copy_n(nearest(*c, x, y, w, h), 3, o);
            else o[0] = o[1] = o[2] = 255;
            o[3] = luminance(nearest(*a, x, y, w, h));
        }
    return png(w, h, out, why);
}

std::optional<std::vector<unsigned char>> metallicRoughnessMap(const std::vector<unsigned char>& roughness,
                                                               const std::vector<unsigned char>& metalness, std::string& why) {
    std::optional<gltf::Rgba8Image> r, m;
    if (!roughness.empty() && !(r = decode(roughness, "the roughness map cannot be decoded", why))) return std::nullopt;
    if (!metalness.empty() && !(m = decode(metalness, "the metalness map cannot be decoded", why))) return std::nullopt;
    if (!r && !m) return why = "no map", std::nullopt;
    const int w = std::max(r ? r->width : 0, m ? m->width : 0), h = std::max(r ? r->height : 0, m ? m->height : 0);
    std::vector<uint8_t> out(size_t(w) * size_t(h) * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            uint8_t* o = &out[(size_t(y) * size_t(w) + size_t(x)) * 4];
            o[0] = 255;  // unused by glTF (occlusion's channel when packed)
            o[1] = r ? luminance(nearest(*r, x, y, w, h)) : 255;
            o[2] = m ? luminance(nearest(*m, x, y, w, h)) : 255;  // the factor alone, as without a map
            o[3] = 255;
        }
    return png(w, h, out, why);
}

}  // namespace rf
