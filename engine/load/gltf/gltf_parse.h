#pragma once
/// A glTF file read, guarded and parsed: the preflight, tinygltf confined to the asset root,
/// compressed geometry decoded. The one way in for the loader (gltf_loader.h) and the
/// inspector (gltf_inspect.h), so both refuse the same files with the same messages.
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/util/file_source.h"
#include "engine/scene/scene_options.h"

namespace rf::gltf {

/// Parses path through fs. Images are kept encoded (keepEncodedImage). Throws InputError(path, …)
/// on anything the preflight, tinygltf or the decoders refuse; what they only warn about goes
/// to notes.
tinygltf::Model parseGltf(const std::string& path, FileSource& fs, const AssetOptions& assets, std::vector<std::string>& notes);

}  // namespace rf::gltf
