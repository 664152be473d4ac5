#include "engine/load/scene_loader.h"
#include "engine/load/model_inspect.h"

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/assimp/assimp_import.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/json_scene_loader.h"
#include "engine/util/load_control.h"
#include "engine/util/model_path.h"
#include "engine/integrators/shadow_catcher.h"

namespace rf {

LoadedScene loadScene(const std::string& path, FileSource& fs, const SceneOptions& options, GltfInfo* inspect) {
    LoadStep step("reading the scene");
    try {
        LoadedScene loaded;
        if (inspect && !isModelPath(path)) *inspect = inspectModel(path, fs, options.assets);  // refuses it
        if (lowerExtension(path) == ".json") loaded = loadJsonScene(path, fs, options);
        else if (isGltfPath(path)) {
            loaded.scene = loadGltfScene(path, fs, options);
            if (inspect) *inspect = inspectGltf(path, fs, options.assets);
        } else if (const std::string what = notRegularFile(path); !what.empty())
            throw InputError(path, "is " + what + ", not a scene file (expected a .json, .gltf or .glb file)");
        else if (isAssimpPath(path)) loaded.scene = loadAssimpScene(path, fs, options, inspect);
        else if (const std::string why = unvouchedAssimpFormat(path); !why.empty()) throw InputError(path, why);
        else throw InputError(path, "unknown scene type (expected .json, .gltf or .glb, or a model in " + assimpFormatList() + ")");
        if (options.ground) placeGround(loaded.scene, *options.ground);
        loaded.timeline.animation = options.animation;
        if (options.camera) {
            loaded.timeline.camera = options.camera;
            loaded.timeline.cameraSource = "--camera";
        }
        return loaded;
    } catch (LoadCancelled& c) {
        if (c.file.empty()) c.file = path;
        throw;
    } catch (const std::bad_alloc&) {
        // Named by the innermost step the exception left (its scope has closed by now).
        throw OutOfMemoryError(path, lastFailedStep());
    }
}

GltfInfo inspectModel(const std::string& path, FileSource& fs, const AssetOptions& assets) {
    if (isGltfPath(path)) return inspectGltf(path, fs, assets);
    if (isAssimpPath(path)) return inspectAssimp(path, fs, assets);
    throw InputError(path, "info describes a model: glTF (.gltf or .glb) or " + assimpFormatList());
}

}  // namespace rf
