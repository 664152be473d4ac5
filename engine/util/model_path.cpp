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

}  // namespace rf
