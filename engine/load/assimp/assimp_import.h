#pragma once
/// Models that are not glTF (OBJ with its MTL and textures, STL, PLY, FBX, COLLADA, 3MF), read
/// through Debian's assimp (the Open Asset Import Library) and turned into the glTF model the
/// glTF loader takes (gltf_loader.h): from there on they are loaded, framed, shaded, broadcast
/// and described exactly as a glTF file is. Every file assimp opens (the model and its side
/// files) is read through the FileSource, confined to the asset root, so the farm's bundle
/// carries them and the workers import the same bytes.
///
/// Mapping (docs/pictures.md has the table): meshes to primitives (POSITION, NORMAL,
/// TEXCOORD_0, COLOR_0 made linear from sRGB), the node tree with its matrices under one root
/// that turns the format's axes and unit into glTF's (Y up, metres), materials to
/// metallic-roughness with KHR_materials_specular and KHR_materials_emissive_strength.
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_inspect.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// The formats read through assimp, for messages: ".obj, .stl, .ply, .fbx, .dae and .3mf".
std::string assimpFormatList();

/// For a path whose extension assimp reads but rayfarm does not vouch for (.3ds, .blend, .x,
/// ...): why it is refused, naming the formats rayfarm reads; "" for any other path.
std::string unvouchedAssimpFormat(const std::string& path);

/// Imports path through fs as a glTF model. Throws InputError(path, …) on a file assimp
/// cannot read, one whose side files leave the asset root, or one with nothing to draw; what is
/// left out (cameras, lights, animations, textures that cannot be used) goes to notes.
tinygltf::Model importAssimpModel(const std::string& path, FileSource& fs, const AssetOptions& assets,
                                  std::vector<std::string>& notes);

/// Appends the model to a scene (a scene file's "model"), as loadGltfModel appends a glTF file.
void loadAssimpModel(Scene& scene, const std::string& path, const DMat4& worldFromModel, FileSource& fs, int materialOverride = -1,
                     const AssetOptions& assets = {});

/// The model as a whole scene, as loadGltfScene makes one of a glTF file; with inspect, also
/// what inspectAssimp says of it, from the same import.
Scene loadAssimpScene(const std::string& path, FileSource& fs, const SceneOptions& options = {}, GltfInfo* inspect = nullptr);

/// What `rayfarm info` says of it: the glTF model it became, with its format named.
GltfInfo inspectAssimp(const std::string& path, FileSource& fs, const AssetOptions& assets = {});

}  // namespace rf
