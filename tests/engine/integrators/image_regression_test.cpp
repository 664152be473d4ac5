// Image regression: small renders of the shipped scenes against reference PNGs in
// tests/engine/reference/ (renderer-generated baselines, reviewed by eye).
//
// Tolerance: a pixel is off if any 8-bit sRGB channel differs by more than kLevels; a scene
// fails if more than kMaxOffFraction of its pixels are off (1-spp edges may flip between
// compilers or with -march=native's FMA contraction; a real change moves far more).
// On failure the render and a false-colour diff go to RAYFARM_TEST_OUT/regression/.
// RAYFARM_UPDATE_REFERENCES=1 rewrites the references instead (review them before committing).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "engine/util/image_metrics.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {
constexpr int kLevels = 3;
constexpr double kMaxOffFraction = 0.005;
constexpr int kWidth = 96, kHeight = 64;

class ImageRegression : public ::testing::TestWithParam<const char*> {};

TEST_P(ImageRegression, MatchesReference) {
    const std::string name = GetParam();
    DiskFileSource fs;
    const LoadedScene sceneLoaded = loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/" + name + ".json", fs);
    const Scene& scene = sceneLoaded.scene;
    RenderSettings rs = scene.settings;
    rs.width = kWidth;
    rs.height = kHeight;
    RayStats st;
    const Image img = renderFrame(scene, {scene.camera, rs}, 0, 0, st);
    const std::vector<uint8_t> got = toRgb8(img, rs.toneMap);
    const std::string refPath = std::string(RAYFARM_SOURCE_DIR) + "/tests/engine/reference/" + name + ".png";
    if (std::getenv("RAYFARM_UPDATE_REFERENCES")) {
        writePng(refPath, kWidth, kHeight, got);
        GTEST_SKIP() << "wrote " << refPath;
    }
    int w = 0, h = 0;
    std::vector<uint8_t> ref;
    ASSERT_NO_THROW(ref = readImageRgb8(refPath, w, h)) << "missing reference; RAYFARM_UPDATE_REFERENCES=1 writes it";
    ASSERT_EQ(w, kWidth);
    ASSERT_EQ(h, kHeight);
    int off = 0, worst = 0;
    for (size_t p = 0; p < got.size(); p += 3) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(got[p + c]) - int(ref[p + c])));
        worst = std::max(worst, d);
        off += d > kLevels;
    }
    const double frac = double(off) / (kWidth * kHeight);
    if (frac > kMaxOffFraction) {
        const std::string dir = std::string(RAYFARM_TEST_OUT) + "/regression";
        std::filesystem::create_directories(dir);
        writePng(dir + "/" + name + "_got.png", kWidth, kHeight, got);
        writePng(dir + "/" + name + "_diff.png", kWidth, kHeight, falseColorErrorRgb8(got, ref, kWidth, kHeight, 32.0));
        ADD_FAILURE() << name << ": " << off << " pixels (" << 100.0 * frac << "%) differ by more than " << kLevels
                      << "/255 (largest " << worst << "); render and diff written to " << dir;
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, ImageRegression,
                         ::testing::Values("whitted", "spot_lights", "glass_tir", "mesh_phong"),
                         [](const auto& info) { return std::string(info.param); });
}  // namespace
