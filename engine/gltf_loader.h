#pragma once
/// glTF 2.0 models (.gltf, .glb) through tinygltf, turned into engine geometry, materials,
/// textures, lights and cameras.
#include <string>

#include "file_source.h"
#include "scene.h"

namespace rf {

/// Appends a model to `scene`, placed by worldFromModel (world space, double precision; the
/// loader rebases by scene.renderOrigin). Throws InputError naming the file on bad input.
void loadGltfModel(Scene& scene, const std::string& path, const DMat4& worldFromModel, FileSource& fs);

/// A bare model as a whole scene: the model, a camera framed on its bounding sphere with a
/// margin, and a default key/fill/rim rig when the model brings no lights.
Scene loadGltfScene(const std::string& path, FileSource& fs);

}  // namespace rf
