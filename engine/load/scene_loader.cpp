#include "engine/load/scene_loader.h"

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/json_scene_loader.h"
#include "engine/util/load_control.h"
#include "engine/util/model_path.h"
#include "engine/integrators/shadow_catcher.h"

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
