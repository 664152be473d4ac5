#pragma once
// Helpers for glTF tests: temporary folders, little-endian byte packing and data URIs, so tests
// can write small hand-made glTF files whose expected results are computed by hand.
#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <nlohmann/json.hpp>

namespace gltftest {

namespace fs = std::filesystem;
using json = nlohmann::json;

/// A fresh directory under the system temp dir, removed when the object goes.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> n{0};
        path = fs::temp_directory_path() / ("rayfarm-gltf-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string operator/(const std::string& rel) const { return (path / rel).string(); }
};

inline void writeFile(const std::string& path, const std::string& bytes) {
    fs::create_directories(fs::path(path).parent_path());
    std::ofstream f(path, std::ios::binary);
    f.write(bytes.data(), std::streamsize(bytes.size()));
}

inline std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

/// Appends the raw bytes of each value (little-endian on every host rayfarm targets).
template <typename T>
void put(std::string& buf, std::initializer_list<T> values) {
    for (T v : values) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        buf.append(b, sizeof(T));
    }
}

inline std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        const uint32_t v = uint8_t(in[i]) << 16;
        out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

inline std::string dataUri(const std::string& bytes) { return "data:application/octet-stream;base64," + base64(bytes); }

/// Three float positions of one triangle: the smallest buffer a model can draw.
inline std::string oneTriangleBytes(float a[3], float b[3], float c[3]) {
    std::string buf;
    put<float>(buf, {a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]});
    return buf;
}

/// glTF with one non-indexed triangle (36 bytes of floats) read from `bufferUri`, on one node.
inline json oneTriangleGltf(const std::string& bufferUri, json node = json::object()) {
    node["mesh"] = 0;
    return json{{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", {0}}}}},
                {"nodes", {node}},
                {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
                {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}}},
                {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}}},
                {"buffers", {{{"uri", bufferUri}, {"byteLength", 36}}}}};
}

}  // namespace gltftest
