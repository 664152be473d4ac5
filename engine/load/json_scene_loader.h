#pragma once
/// JSON scene files: camera, materials, lights, shapes, glTF models placed in the scene, and
/// the timeline sections (kept as parsed JSON for anim/).
#include <string>

#include "engine/util/file_source.h"
#include "engine/load/loaded_scene.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// Loads a JSON scene file; it is ready to render (built). Errors throw InputError naming the
/// file and the JSON path.
LoadedScene loadJsonScene(const std::string& path, FileSource& fs, const SceneOptions& options = {});

}  // namespace rf
