#pragma once
/// The material lookup at a surface point: which texture coordinates a texture reads, its
/// KHR_texture_transform, and the factor × texture products. Shading and the alpha-MASK test
/// during traversal both read materials through here, so they cannot disagree.
#include "engine/materials/material.h"
#include "engine/materials/texture.h"

namespace rf {

struct SurfaceInteraction;

/// The coordinates texture slot t reads at a point with TEXCOORD_0 = uv0 and TEXCOORD_1 = uv1:
/// the set t.texCoord names, through t's transform.
inline Vec2 textureUv(const TextureTransform& t, Vec2 uv0, Vec2 uv1) {
    return applyTextureTransform(t, t.texCoord == 1 ? uv1 : uv0);
}

/// The texture-coordinate area a lookup through slot t covers, from the footprint per set
/// (SurfaceInteraction::uvArea: TEXCOORD_0 in x, TEXCOORD_1 in y) and t's transform.
inline float textureFootprint(const TextureTransform& t, Vec2 area) {
    return (t.texCoord == 1 ? area.y : area.x) * textureTransformAreaScale(t);
}

/// The base-colour texture's RGBA at (uv0, uv1), filtered over a footprint of area (per set,
/// as textureFootprint; 0: unfiltered); white where m has none.
Vec4 baseColorTexel(const std::vector<Texture>& textures, const Material& m, Vec2 uv0, Vec2 uv1, Vec2 area = Vec2(0.f));

/// Alpha factor × texture alpha: what the alpha-MASK test compares with the cut-off (unfiltered:
/// traversal has no footprint, and a cut-out edge stays where the texture puts it).
inline float materialAlpha(const std::vector<Texture>& textures, const Material& m, Vec2 uv0, Vec2 uv1) {
    return m.baseColorTexture >= 0 ? m.alpha * baseColorTexel(textures, m, uv0, uv1).a : m.alpha;
}

/// Base colour of material m at a surface point (checker, texture, factor) × the vertex colour
/// (COLOR_0); *alpha gets the alpha factor × texture alpha × vertex alpha when asked for. The
/// checker is laid out in world space: render space plus renderOrigin. (scene.h has the
/// overload that takes the scene.)
Color baseColor(const Material& m, const std::vector<Texture>& textures, const DVec3& renderOrigin,
                const SurfaceInteraction& si, float* alpha = nullptr);

/// The tangent-space normal of m's normal texture at (uv0, uv1), scaled by normalScale in x and
/// y as glTF defines it (not normalised). Only for materials with a normal texture.
Vec3 normalTextureSample(const std::vector<Texture>& textures, const Material& m, Vec2 uv0, Vec2 uv1, Vec2 area = Vec2(0.f));

}  // namespace rf
