#pragma once
/// Loads a scene from a JSON scene file or a glTF model (.gltf/.glb). Errors throw InputError
/// naming the file and the JSON path: "scenes/x.json: lights[2].color: expected 3 numbers".
#include <string>

#include "engine/util/file_source.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// Loads path through fs, choosing the loader by the extension (json_scene_loader.h,
/// gltf_loader.h): the one place that knows both. The scene is ready to render (built).
Scene loadScene(const std::string& path, FileSource& fs, const SceneOptions& options = {});

}  // namespace rf
