#pragma once
/// Maps that these formats keep apart and glTF keeps in one texture, combined into a PNG the
/// glTF loader then reads as any texture:
/// - an opacity map (MTL's map_d, FBX's and COLLADA's transparency texture) becomes the alpha of
///   the base colour texture (glTF takes alpha from there);
/// - a roughness map and a metalness map (MTL's map_Pr and map_Pm, FBX's) become glTF's
///   metallicRoughness texture: roughness in G, metalness in B.
/// A map's value is its luminance (grey maps are what the formats hold); two maps of different
/// sizes meet at the larger, the smaller sampled by nearest texel.
#include <optional>
#include <string>
#include <vector>

namespace rf {

/// colour (encoded bytes; empty: white) with its alpha from opacity's luminance. nullopt, with
/// why, when an image cannot be decoded.
std::optional<std::vector<unsigned char>> withOpacityMap(const std::vector<unsigned char>& colour, const std::vector<unsigned char>& opacity,
                                                         std::string& why);

/// glTF's metallicRoughness texture from a roughness and a metalness map (either may be empty:
/// its channel then 1, so that the factor alone sets it, as without a map).
std::optional<std::vector<unsigned char>> metallicRoughnessMap(const std::vector<unsigned char>& roughness,
                                                               const std::vector<unsigned char>& metalness, std::string& why);

}  // namespace rf
