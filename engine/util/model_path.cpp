#include "engine/util/model_path.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace rf {

std::string lowerExtension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e;
}

bool isGltfPath(const std::string& path) {
    const std::string e = lowerExtension(path);
    return e == ".gltf" || e == ".glb";
}

bool isAssimpPath(const std::string& path) {
    const std::string e = lowerExtension(path);
    return e == ".obj" || e == ".stl" || e == ".ply" || e == ".fbx" || e == ".dae" || e == ".3mf";
}

bool isModelPath(const std::string& path) { return isGltfPath(path) || isAssimpPath(path); }

}  // namespace rf
