#pragma once
/// Loads a scene from a JSON scene file or a glTF model (.gltf/.glb). Errors throw InputError
/// naming the file and the JSON path: "scenes/x.json: lights[2].color: expected 3 numbers".
#include <string>

#include "file_source.h"
#include "scene.h"
#include "scene_options.h"

namespace rf {

/// Loads path through fs, dispatching on the extension. The scene is ready to render (built).
Scene loadScene(const std::string& path, FileSource& fs, const SceneOptions& options = {});

/// Loads a JSON scene file.
Scene loadJsonScene(const std::string& path, FileSource& fs, const SceneOptions& options = {});

/// The render-space origin for a scene whose camera looks at `target`: the target rounded to a
/// multiple of 64, so geometry near the camera's focus keeps float precision.
DVec3 chooseRenderOrigin(const DVec3& target);

}  // namespace rf
