#pragma once
/// Decoded textures in linear float RGBA, sampled with glTF wrap and filter rules, and mip-mapped
/// so a texture seen from afar reads as its average over the pixel, not as aliased samples.
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/util/vec_math.h"

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

/// A scene's decoded textures. They never change once loaded, so copies of a scene share them:
/// the auto-exposure probe, a posed frame's copy and a worker's scene would otherwise each
/// double a film's largest allocation (an 8192² texture and its mip-maps are 1.4 GB).
/// Adding to a set that another copy shares first takes a copy of its own (loading only).
class TextureSet {
public:
    const Texture& operator[](size_t i) const { return (*textures_)[i]; }
    size_t size() const { return textures_->size(); }
    bool empty() const { return textures_->empty(); }
    std::vector<Texture>::const_iterator begin() const { return textures_->begin(); }
    std::vector<Texture>::const_iterator end() const { return textures_->end(); }
    operator const std::vector<Texture>&() const { return *textures_; }
    void push_back(Texture t) {
        if (textures_.use_count() > 1) textures_ = std::make_shared<std::vector<Texture>>(*textures_);
        textures_->push_back(std::move(t));
    }
    /// Whether two sets are one in memory (tests).
    bool sharedWith(const TextureSet& o) const { return textures_ == o.textures_; }

private:
    std::shared_ptr<std::vector<Texture>> textures_ = std::make_shared<std::vector<Texture>>();
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
