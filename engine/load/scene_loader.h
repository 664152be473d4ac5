#pragma once
/// Loads a scene from a JSON scene file or a glTF model (.gltf/.glb). Errors throw InputError
/// naming the file and the JSON path: "scenes/x.json: lights[2].color: expected 3 numbers".
#include <string>

#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_inspect.h"
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// Loads path through fs, choosing the loader by the extension (json_scene_loader.h,
/// gltf_loader.h): the one place that knows both. The scene is ready to render (built); its
/// timeline source carries the file's animation sections and options.animation. With inspect, a
/// model (not a scene file) is also described there as inspectModel does (model_inspect.h), from
/// the same read: a model through assimp is imported once, not twice (`rayfarm info`).
LoadedScene loadScene(const std::string& path, FileSource& fs, const SceneOptions& options = {}, GltfInfo* inspect = nullptr);

}  // namespace rf
