#pragma once
/// What a scene path names, told by its extension: the one place that knows which extensions
/// are models, for the loader, the timeline (a bare model's default turntable) and the CLI.
#include <string>

namespace rf {

/// The path's extension in lower case, with its dot (".glb"), or "" if it has none.
std::string lowerExtension(const std::string& path);

/// Whether path names a glTF 2.0 model (.gltf or .glb, any case).
bool isGltfPath(const std::string& path);

/// Whether path names a model rayfarm reads through assimp (engine/load/assimp/): .obj, .stl,
/// .ply, .fbx, .dae or .3mf, any case.
bool isAssimpPath(const std::string& path);

/// A bare model (glTF, or a format read through assimp), as opposed to a scene file.
bool isModelPath(const std::string& path);

}  // namespace rf
