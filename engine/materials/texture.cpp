#include "engine/materials/texture.h"

#include <algorithm>

#include "engine/util/load_control.h"

namespace rf {

namespace {
int wrapIndex(int i, int n, Wrap w) {
    switch (w) {
        case Wrap::ClampToEdge: return std::clamp(i, 0, n - 1);
        case Wrap::MirroredRepeat: {
            const int period = 2 * n;
            int m = i % period;
            if (m < 0) m += period;
            return m < n ? m : period - 1 - m;
        }
        case Wrap::Repeat:
        default: {
            int m = i % n;
            return m < 0 ? m + n : m;
        }
    }
}

/// One image's texels at uv, bilinear (or nearest), with the texture's wrap modes.
Vec4 sampleImage(const Vec4* texels, int width, int height, Wrap wrapS, Wrap wrapT, Filter filter, Vec2 uv) {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = Vec2(0.f);
    // Keep the coordinate small before converting to int: wrap modes are periodic anyway.
    const float x = uv.x * width - 0.5f, y = uv.y * height - 0.5f;
    auto at = [&](int i, int j) { return texels[size_t(wrapIndex(j, height, wrapT)) * width + wrapIndex(i, width, wrapS)]; };
    const float fx = std::floor(x), fy = std::floor(y);
    const double limit = 1 << 30;
    if (std::abs(fx) > limit || std::abs(fy) > limit) return at(0, 0);
    const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy);
    if (filter == Filter::Nearest) return at(static_cast<int>(std::floor(x + 0.5f)), static_cast<int>(std::floor(y + 0.5f)));
    const float tx = x - fx, ty = y - fy;
    return (1 - ty) * ((1 - tx) * at(i0, j0) + tx * at(i0 + 1, j0)) + ty * ((1 - tx) * at(i0, j0 + 1) + tx * at(i0 + 1, j0 + 1));
}

/// The level below src: each texel the mean of the (up to) 2×2 texels it covers.
TextureLevel halve(const Vec4* src, int w, int h) {
    TextureLevel out;
    out.width = std::max(1, (w + 1) / 2);
    out.height = std::max(1, (h + 1) / 2);
    out.texels.reserve(size_t(out.width) * out.height);  // appended in order: no zeroing first
    for (int y = 0; y < out.height; ++y) {
        if (y % 256 == 0) pollLoadCancel();  // only loads make mip-maps
        for (int x = 0; x < out.width; ++x) {
            Vec4 sum(0.f);
            int n = 0;
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const int sx = 2 * x + dx, sy = 2 * y + dy;
                    if (sx >= w || sy >= h) continue;
                    sum += src[size_t(sy) * w + sx];
                    ++n;
                }
            out.texels.push_back(sum / float(n));
        }
    }
    return out;
}
}  // namespace

void buildMipmaps(Texture& tex) {
    tex.mips.clear();
    const Vec4* src = tex.texels.data();
    int w = tex.width, h = tex.height;
    while (w > 1 || h > 1) {
        tex.mips.push_back(halve(src, w, h));
        src = tex.mips.back().texels.data();
        w = tex.mips.back().width;
        h = tex.mips.back().height;
    }
}

Vec4 sampleTexture(const Texture& tex, Vec2 uv) {
    if (tex.width <= 0 || tex.height <= 0) return Vec4(1.f);
    return sampleImage(tex.texels.data(), tex.width, tex.height, tex.wrapS, tex.wrapT, tex.filter, uv);
}

Vec4 sampleTexture(const Texture& tex, Vec2 uv, float uvArea) {
    // Level λ has texels 2^λ times level 0's: λ = ½·log2(footprint in level-0 texels).
    const float texels = uvArea * float(tex.width) * float(tex.height);
    if (!(texels > 1.f) || tex.mips.empty()) return sampleTexture(tex, uv);
    const float lod = std::min(0.5f * std::log2(texels), float(tex.mips.size()));
    const int l0 = int(lod);
    const float t = lod - float(l0);
    auto level = [&](int l) {
        if (l == 0) return sampleImage(tex.texels.data(), tex.width, tex.height, tex.wrapS, tex.wrapT, Filter::Linear, uv);
        const TextureLevel& m = tex.mips[size_t(l - 1)];
        return sampleImage(m.texels.data(), m.width, m.height, tex.wrapS, tex.wrapT, Filter::Linear, uv);
    };
    const Vec4 a = level(l0);
    return t > 0.f && l0 < int(tex.mips.size()) ? glm::mix(a, level(l0 + 1), t) : a;
}

}  // namespace rf

#include "engine/materials/material.h"

namespace rf {

Vec2 applyTextureTransform(const TextureTransform& t, Vec2 uv) {
    if (t.identity()) return uv;
    const float c = std::cos(t.rotation), s = std::sin(t.rotation);
    const Vec2 su = t.scale * uv;
    // The extension's matrix is column-major mat3(c, s, 0, −s, c, 0, 0, 0, 1) transposed:
    // x' = c·x + s·y, y' = −s·x + c·y.
    return t.offset + Vec2(c * su.x + s * su.y, -s * su.x + c * su.y);
}

float textureTransformAreaScale(const TextureTransform& t) { return std::abs(t.scale.x * t.scale.y); }

}  // namespace rf
