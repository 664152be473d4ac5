// The pruning rule (--min-weight) compares what a light adds to the displayed pixel, after
// exposure: a scene in small units (a 10 cd lamp) shown at its metered EV keeps its light, and
// scaling every light by k while lowering the exposure by log2 k leaves the picture unchanged.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {

const std::string kDim = std::string(RAYFARM_SOURCE_DIR) + "/scenes/dim_light/dim_light.gltf";

std::vector<uint8_t> render8(const Scene& scene, float ev, float minWeight) {
    RenderSettings s = scene.settings;
    s.width = 160;
    s.height = 90;
    s.spp = 1;
    s.autoExposure = false;
    s.exposure = ev;
    s.minWeight = minWeight;
    RayStats rays;
    return toRgb8(renderFrame(scene, {scene.camera, s}, 0, 2, rays), s);
}

double fractionDiffering(const std::vector<uint8_t>& x, const std::vector<uint8_t>& y, int tol) {
    size_t off = 0;
    for (size_t p = 0; p < x.size(); p += 3) {
        bool bad = false;
        for (int c = 0; c < 3; ++c) bad |= std::abs(int(x[p + c]) - int(y[p + c])) > tol;
        off += bad;
    }
    return double(off) / double(x.size() / 3);
}

double meanLevel(const std::vector<uint8_t>& px) {
    double sum = 0.0;
    for (uint8_t v : px) sum += v;
    return sum / double(px.size());
}

}  // namespace

// scenes/dim_light: one 10 cd point light over a floor and a box, through the file's camera. At
// the EV that shows it (+9.7), the default --min-weight gives the unpruned picture to the byte;
// before the rule counted exposure it pruned every light term (each < 1e-3 W/sr·m⁻² before
// exposure) and the frame was black.
TEST(Pruning, DimLightSceneKeepsItsLightAtTheDefaultMinWeight) {
    DiskFileSource fs;
    LoadedScene sceneLoaded = loadScene(kDim, fs);
    Scene& scene = sceneLoaded.scene;
    useGltfCamera(scene, 0);
    const RenderSettings defaults;
    const std::vector<uint8_t> pruned = render8(scene, 9.7f, defaults.minWeight);
    const std::vector<uint8_t> full = render8(scene, 9.7f, 0.f);
    EXPECT_GT(meanLevel(full), 40.0) << "the lamp lights the floor and the box";
    EXPECT_TRUE(pruned == full) << "mean " << meanLevel(pruned) << " pruned vs " << meanLevel(full);
}

// The units cannot matter: every light ×1e-6 and the exposure +log2(1e6) is the same picture
// (within one level on 0.1% of pixels: 2^EV and the lights' scale round differently), and the
// pruning keeps as much of it.
TEST(Pruning, LightUnitsScaledAwayByExposureGiveTheSamePicture) {
    DiskFileSource fs;
    LoadedScene sceneLoaded = loadScene(kDim, fs);
    Scene& scene = sceneLoaded.scene;
    useGltfCamera(scene, 0);
    const std::vector<uint8_t> ref = render8(scene, 9.7f, 1e-3f);
    for (Light& l : scene.lights) l.intensity *= 1e-6f;
    const std::vector<uint8_t> small = render8(scene, 9.7f + float(std::log2(1e6)), 1e-3f);
    EXPECT_LE(fractionDiffering(small, ref, 1), 0.001);
}
