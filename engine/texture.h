#pragma once
/// Decoded textures in linear float RGBA, sampled with glTF wrap and filter rules.
#include <cstdint>
#include <vector>

#include "vec_math.h"

namespace rf {

enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };
enum class Filter { Nearest, Linear };

struct Texture {
    int width = 0, height = 0;
    std::vector<Vec4> texels;  ///< linear RGBA, row 0 at the top (v = 0)
    Wrap wrapS = Wrap::Repeat, wrapT = Wrap::Repeat;
    Filter filter = Filter::Linear;
};

/// Sample at uv (v down, as glTF). Empty textures return white.
Vec4 sampleTexture(const Texture& tex, Vec2 uv);

}  // namespace rf

namespace rf {
struct TextureTransform;
/// uv' = offset + R(rotation) · (scale ⊙ uv), as KHR_texture_transform defines it.
Vec2 applyTextureTransform(const TextureTransform& t, Vec2 uv);
}  // namespace rf
