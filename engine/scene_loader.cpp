#include "scene_loader.h"

#include "errors.h"
#include "gltf_loader.h"
#include "json_scene_loader.h"
#include "model_path.h"
#include "shadow_catcher.h"

namespace rf {

Scene loadScene(const std::string& path, FileSource& fs, const SceneOptions& options) {
    Scene s;
    if (lowerExtension(path) == ".json") s = loadJsonScene(path, fs, options);
    else if (isGltfPath(path)) s = loadGltfScene(path, fs, options);
    else throw InputError(path, "unknown scene type (expected .json, .gltf or .glb)");
    if (options.ground) placeGround(s, *options.ground);
    s.animation = options.animation;
    return s;
}

}  // namespace rf
