#pragma once
/// glTF 2.0 models (.gltf, .glb) through tinygltf, turned into engine geometry, materials,
/// textures, lights and cameras.
///
/// Mapping choices (see also gltf_materials.h):
/// - Render space = world − scene.renderOrigin; node transforms are composed in double.
/// - Meshes on nodes that an animation targets (or below one) keep model-space data and a
///   (model, node) link for SceneGeometry::applyNodeTransforms; all others are baked.
/// - KHR_lights_punctual: point/spot intensity in candela becomes intensity/π with inverse-square
///   attenuation (1/d² of a Lambertian surface's radiance, exposure 1); directional lux/π.
/// - alphaMode BLEND: blended over what is behind it, unbent, with alpha = factor × texture alpha ×
///   vertex alpha per hit (material_gltf.h, gltfCoverage), in the picture and in shadow rays.
/// - glTF cameras (perspective and orthographic, in node order) go to Scene::gltfCameras;
///   useGltfCamera() picks one.
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}  // namespace tinygltf

#include "engine/util/file_source.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// Appends a model to `scene`, placed by worldFromModel (world space, double precision; the
/// loader rebases by scene.renderOrigin). Throws InputError naming the file on bad input.
/// materialOverride ≥ 0 (a scene material): every primitive in it, without vertex colours or
/// tangents; the file's materials and textures are then not read at all. assets: the asset root
/// its URIs must stay inside, the texture limits and the material variant (scene_options.h).
/// Returns how many material variants (KHR_materials_variants) the file names.
size_t loadGltfModel(Scene& scene, const std::string& path, const DMat4& worldFromModel, FileSource& fs,
                     int materialOverride = -1, const AssetOptions& assets = {});

/// The same for a glTF model made in memory from another format (engine/load/assimp/), with the
/// notes its import gathered.
size_t loadGltfModel(Scene& scene, const std::string& path, tinygltf::Model model, std::vector<std::string> notes,
                     const DMat4& worldFromModel, int materialOverride = -1, const AssetOptions& assets = {});

/// A bare model as a whole scene: the model, a camera framed on its bounding sphere with a
/// margin, and a default key/fill/rim rig when the model brings no lights; the environment
/// options name (none by default).
Scene loadGltfScene(const std::string& path, FileSource& fs, const SceneOptions& options = {});
/// The same for a glTF model made in memory from another format (engine/load/assimp/), with
/// the notes its import gathered: framed, lit and built exactly as a file would be.
Scene loadGltfScene(const std::string& path, tinygltf::Model model, std::vector<std::string> notes, FileSource& fs,
                    const SceneOptions& options = {});

/// scene.gltfCameras[index]; throws InputError if there is none, or if the file's camera is
/// unusable (a yfov of 0), naming the file and the camera.
const Camera& chosenGltfCamera(const Scene& scene, int index);
/// Makes chosenGltfCamera(scene, index) the render camera.
void useGltfCamera(Scene& scene, int index);

}  // namespace rf
