#include "texture.h"

#include <algorithm>

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
}  // namespace

Vec4 sampleTexture(const Texture& tex, Vec2 uv) {
    if (tex.width <= 0 || tex.height <= 0) return Vec4(1.f);
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = Vec2(0.f);
    // Keep the coordinate small before converting to int: wrap modes are periodic anyway.
    const float x = uv.x * tex.width - 0.5f, y = uv.y * tex.height - 0.5f;
    auto at = [&](int i, int j) {
        return tex.texels[size_t(wrapIndex(j, tex.height, tex.wrapT)) * tex.width + wrapIndex(i, tex.width, tex.wrapS)];
    };
    const float fx = std::floor(x), fy = std::floor(y);
    const double limit = 1 << 30;
    if (std::abs(fx) > limit || std::abs(fy) > limit) return at(0, 0);
    const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy);
    if (tex.filter == Filter::Nearest) return at(static_cast<int>(std::floor(x + 0.5f)), static_cast<int>(std::floor(y + 0.5f)));
    const float tx = x - fx, ty = y - fy;
    return (1 - ty) * ((1 - tx) * at(i0, j0) + tx * at(i0 + 1, j0)) + ty * ((1 - tx) * at(i0, j0 + 1) + tx * at(i0 + 1, j0 + 1));
}

}  // namespace rf

#include "material.h"

namespace rf {

Vec2 applyTextureTransform(const TextureTransform& t, Vec2 uv) {
    if (t.identity()) return uv;
    const float c = std::cos(t.rotation), s = std::sin(t.rotation);
    const Vec2 su = t.scale * uv;
    // The extension's matrix is column-major mat3(c, s, 0, −s, c, 0, 0, 0, 1) transposed:
    // x' = c·x + s·y, y' = −s·x + c·y.
    return t.offset + Vec2(c * su.x + s * su.y, -s * su.x + c * su.y);
}

}  // namespace rf
