#pragma once
/// KHR_materials_variants: a file names material variants (a sofa in red, in green...) and maps
/// each primitive to another material per variant; `--variant NAME` (a scene file's model key
/// "variant") picks one. Without a choice, or for a primitive the variant does not map, the
/// primitive keeps its own material, as the extension says.
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace rf::gltf {

/// The file's variant names, in the order the root extension lists them ("" for an unnamed one).
std::vector<std::string> materialVariants(const tinygltf::Model& model);

/// "3: \"red\", \"green\", \"blue\"": what a message about a missing variant lists.
std::string listVariants(const std::vector<std::string>& names);

/// The index of `name` among the file's variants; throws InputError(file, what + ": ...") listing
/// them when there is none by that name, or when the file has no variants at all. Checks every
/// primitive's mappings on the way (a mapping to a material or variant the file lacks is refused).
int chooseVariant(const tinygltf::Model& model, const std::string& file, const std::string& name, const std::string& what);

/// The material primitive p shows under variant v (≥ 0), or its own when no mapping names v.
int variantMaterial(const tinygltf::Primitive& p, int variant);

}  // namespace rf::gltf
