#pragma once
/// Decoded textures in linear float RGBA, sampled with glTF wrap and filter rules, and mip-mapped
/// so a texture seen from afar reads as its average over the pixel, not as aliased samples.
#include <cstdint>
#include <vector>

#include "vec_math.h"

namespace rf {

enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };
enum class Filter { Nearest, Linear };

/// One image of a mip chain.
struct TextureLevel {
    int width = 0, height = 0;
    std::vector<Vec4> texels;  ///< linear RGBA, row 0 at the top (v = 0)
};

struct Texture {
    int width = 0, height = 0;
    std::vector<Vec4> texels;  ///< linear RGBA, row 0 at the top (v = 0)
    Wrap wrapS = Wrap::Repeat, wrapT = Wrap::Repeat;
    Filter filter = Filter::Linear;  ///< magnification (glTF magFilter); minification is trilinear
    /// Levels 1, 2, ...: each the one above halved (2×2 box, odd sizes rounded up) down to
    /// 1×1; empty until buildMipmaps.
    std::vector<TextureLevel> mips;
};

/// Fills tex.mips from tex.texels.
void buildMipmaps(Texture& tex);

/// Sample at uv (v down, as glTF). Empty textures return white.
Vec4 sampleTexture(const Texture& tex, Vec2 uv);
/// Sample at uv for a footprint of uvArea (the area of texture coordinates one sample covers;
/// 0: a point): where that covers no more than a texel, exactly sampleTexture(tex, uv); beyond,
/// trilinear between the two mip levels whose texels are the footprint's size.
Vec4 sampleTexture(const Texture& tex, Vec2 uv, float uvArea);

}  // namespace rf

namespace rf {
struct TextureTransform;
/// uv' = offset + R(rotation) · (scale ⊙ uv), as KHR_texture_transform defines it.
Vec2 applyTextureTransform(const TextureTransform& t, Vec2 uv);
/// How much t scales areas in texture coordinates (|scale.x · scale.y|; rotation keeps them).
float textureTransformAreaScale(const TextureTransform& t);
}  // namespace rf
