#pragma once
/// What `rayfarm info` describes: a glTF file, or a model read through assimp (load/assimp/) as
/// the glTF model it became, its format named.
#include <string>

#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_inspect.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// Throws InputError naming the file for anything but a model, and for what the loader refuses.
GltfInfo inspectModel(const std::string& path, FileSource& fs, const AssetOptions& assets = {});

}  // namespace rf
