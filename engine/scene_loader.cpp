#include "scene_loader.h"

#include "errors.h"
#include "gltf_loader.h"
#include "json_scene_loader.h"
#include "load_control.h"
#include "model_path.h"
#include "shadow_catcher.h"

namespace rf {

Scene loadScene(const std::string& path, FileSource& fs, const SceneOptions& options) {
    LoadStep step("reading the scene");
    try {
        Scene s;
        if (lowerExtension(path) == ".json") s = loadJsonScene(path, fs, options);
        else if (isGltfPath(path)) s = loadGltfScene(path, fs, options);
        else throw InputError(path, "unknown scene type (expected .json, .gltf or .glb)");
        if (options.ground) placeGround(s, *options.ground);
        s.animation = options.animation;
        return s;
    } catch (LoadCancelled& c) {
        if (c.file.empty()) c.file = path;
        throw;
    } catch (const std::bad_alloc&) {
        // Named by the innermost step the exception left (its scope has closed by now).
        throw OutOfMemoryError(path, lastFailedStep());
    }
}

}  // namespace rf
