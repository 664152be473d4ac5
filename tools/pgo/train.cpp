// The training run of profile-guided optimisation (RAYFARM_PGO in the top CMakeLists.txt): a
// few small frames of each path a render spends its time in, so that the compiler lays the
// engine out for them. It renders with the engine's own frame loop and display mapping, on one
// thread, and prints nothing but errors. Not a test and not a benchmark.
//   pgo_train SOURCE_DIR
#include <cstdio>
#include <string>
#include <vector>

#include "engine/util/errors.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

using namespace rf;

namespace {

void train(const std::string& path, const SceneOptions& options, std::vector<int> frames, int spp, int width = 160) {
    DiskFileSource fs;
    LoadedScene loaded = loadScene(path, fs, options);
    Scene& scene = loaded.scene;
    const anim::Timeline timeline = anim::Timeline::fromScene(loaded);
    RenderSettings settings = scene.settings;
    settings.width = width;
    settings.height = width * 9 / 16;
    settings.spp = spp;
    const auto bounceSlot = std::make_shared<SceneCacheSlot>();  // the film's, as a render job keeps it
    for (int f : frames) {
        if (f < timeline.frameCount()) timeline.applyFrame(scene, f);
        RayStats rays;
        const Image img = renderFrame(scene, {scene.camera, settings, bounceSlot}, f, 1, rays);
        std::vector<uint8_t> rgb(size_t(img.width()) * img.height() * 3);
        encodeRgb8(img.data(), rgb.size(), settings.toneMap, rgb.data(), exposureScale(settings.exposure));
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: pgo_train SOURCE_DIR\n");
        return 2;
    }
    const std::string scenes = std::string(argv[1]) + "/scenes/";
    try {
        // The seed's Phong model: spheres and a plane without a BVH, reflection and refraction.
        train(scenes + "whitted.json", {}, {0, 4, 8, 12, 16, 20, 24, 28}, 1, 320);
        train(scenes + "glass_tir.json", {}, {0}, 1);
        // Phong on triangle meshes through the BVH, spot lights.
        train(scenes + "mesh_phong.json", {}, {0}, 1);
        train(scenes + "spot_lights.json", {}, {0}, 1);
        // glTF's metallic-roughness model with textures under the built-in studio environment
        // and a shadow catcher, at the glTF default of 4 samples; then with its own lights.
        SceneOptions studio;
        studio.environment = EnvironmentSpec{};
        studio.ground = Ground::Shadow;
        train(scenes + "pbr_grid/pbr_grid.gltf", studio, {0, 30}, 4);
        train(scenes + "pbr_grid/pbr_grid.gltf", {}, {0}, 1);
        // A glTF animation on its node.
        train(scenes + "animated_node.gltf", studio, {0, 10}, 1);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pgo_train: %s\n", e.what());
        return 1;
    }
    return 0;
}
