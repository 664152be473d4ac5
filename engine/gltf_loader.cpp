#include "gltf_loader.h"

#include "errors.h"

namespace rf {

// Placeholder until the glTF issue lands: refuse clearly rather than crash.
void loadGltfModel(Scene&, const std::string& path, const DMat4&, FileSource&) {
    throw InputError(path, "glTF models are not supported by this build yet");
}

Scene loadGltfScene(const std::string& path, FileSource& fs) {
    Scene s;
    loadGltfModel(s, path, DMat4(1.0), fs);
    return s;
}

}  // namespace rf
