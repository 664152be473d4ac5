#pragma once
// A glTF floor seen from above, for material-extension tests: a 20×20 floor at y = 0 in one
// material, under a point light, rendered straight down in linear radiance at exposure 0.
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "engine/scene/env_lighting.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/integrators/render.h"

namespace gltftest {

using namespace rf;

/// A 20×20 floor at y = 0 facing +y in material 0, a point light 1 above its centre; images:
/// 2×1 PNGs (left | right texels) the materials may use.
/// edit (if given) changes the document before it is written (more materials, extensions);
/// options: as the command line would give them.
inline Scene loadFloor(const json& material, const std::vector<std::array<uint8_t, 6>>& pngs = {},
                       const std::function<void(json&)>& edit = nullptr, const SceneOptions& options = {}) {
    TempDir dir;
    std::string buf;
    put<float>(buf, {-10, 0, -10, -10, 0, 10, 10, 0, 10, 10, 0, -10});
    put<float>(buf, {0, 0, 0, 1, 1, 1, 1, 0});
    put<uint16_t>(buf, {0, 1, 2, 0, 2, 3});
    json images = json::array(), textures = json::array();
    for (size_t i = 0; i < pngs.size(); ++i) {
        // Appended, not "t" + std::string&&: that trips GCC 12's false -Wrestrict (PR 105651) at
        // -O3 without link-time optimisation, which -Werror makes a failed build.
        std::string name = "t";
        name += std::to_string(i);
        name += ".png";
        writePng(dir / name, 2, 1, std::vector<uint8_t>(pngs[i].begin(), pngs[i].end()));
        images.push_back({{"uri", name}});
        textures.push_back({{"source", i}, {"sampler", 0}});
    }
    json g{{"asset", {{"version", "2.0"}}},
           {"extensionsUsed", {"KHR_materials_unlit", "KHR_materials_clearcoat", "KHR_materials_specular", "KHR_materials_sheen",
                               "KHR_lights_punctual"}},
           {"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 683}}}}}}}},
           {"scene", 0},
           {"scenes", {{{"nodes", {0, 1}}}}},
           {"nodes", {{{"mesh", 0}}, {{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}}},
           {"materials", {material}},
           {"samplers", {{{"magFilter", 9728}, {"minFilter", 9728}}}},
           {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"TEXCOORD_0", 1}}}, {"indices", 2}, {"material", 0}}}}}}},
           {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {-10, 0, -10}}, {"max", {10, 0, 10}}},
                          {{"bufferView", 1}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}},
                          {{"bufferView", 2}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
           {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 32}},
                            {{"buffer", 0}, {"byteOffset", 80}, {"byteLength", 12}}}},
           {"buffers", {{{"uri", dataUri(buf)}, {"byteLength", buf.size()}}}}};
    if (!images.empty()) {
        g["images"] = images;
        g["textures"] = textures;
    }
    if (edit) edit(g);
    writeFile(dir / "m.gltf", g.dump());
    DiskFileSource files;
    return loadGltfScene(dir / "m.gltf", files, options);
}

inline std::shared_ptr<const EnvironmentLight> uniformEnvironment(float radiance) {
    EquirectImage img;
    img.width = 16;
    img.height = 8;
    img.texels.assign(16 * 8, Color(radiance));
    return std::make_shared<const EnvironmentLight>(img, 0.f, 1.f, 1);
}

/// 65×65 from 3 above the centre looking down (fov 0.5 rad), linear radiance, exposure 0.
inline Image renderFromAbove(Scene s) {
    s.camera.eye = Vec3(0.f, 3.f, 0.f);
    s.camera.target = Vec3(0.f);
    s.camera.up = Vec3(0.f, 0.f, -1.f);
    s.camera.fovDeg = float(glm::degrees(0.5));
    RenderSettings rs = s.settings;
    rs.spp = 1;
    rs.width = rs.height = 65;
    rs.exposure = 0.f;
    rs.autoExposure = false;
    RayStats stats;
    return renderFrame(s, {s.camera, rs}, 0, 1, stats);
}

/// n·v at pixel (x, y): the ray through the pixel centre meets the floor's normal +y.
inline float cosineAt(int x, int y) {
    const float t = std::tan(0.25f);
    const Vec3 d = glm::normalize(Vec3((2.f * (x + 0.5f) / 65.f - 1.f) * t, -1.f, (2.f * (y + 0.5f) / 65.f - 1.f) * t));
    return -d.y;
}

}  // namespace gltftest
