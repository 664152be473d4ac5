#pragma once
/// Compressed glTF geometry decoded into plain buffers before anything reads an accessor, so
/// the decoded data goes through the same accessor and bufferView bounds checks as a file's own:
/// - KHR_draco_mesh_compression (Debian's libdraco): each compressed primitive's attributes and
///   indices become new buffers, bufferViews and accessors in the accessors' declared types;
/// - EXT_meshopt_compression / KHR_meshopt_compression (libmeshoptimizer's decoders, with the
///   OCTAHEDRAL, QUATERNION and EXPONENTIAL filters): each compressed bufferView is decoded
///   into a new buffer and pointed at it.
/// Malformed compressed data throws InputError(file, "meshes[i].primitives[j]: ...") in one line.
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace rf::gltf {

/// Decodes every compressed bufferView and primitive of the model in place. notes (if given)
/// gets a line where a Draco primitive's accessors declare counts other than what it decodes.
void decodeCompressedGeometry(tinygltf::Model& model, const std::string& file, std::vector<std::string>* notes = nullptr);

}  // namespace rf::gltf
