// pbr_grid against Blender Cycles: the glTF material model, photometric lights at --exposure 0
// and the studio environment, scored with SSIM and PSNR on the tone-mapped 8-bit images as
// `rayfarm still pbr_grid.gltf --camera 0 --exposure 0 --tonemap clamp [--environment
// studio.exr]` renders them. Cycles path-traces (caustics, real occlusion, blurred
// reflections of other objects); a Whitted tracer is not expected to match those pixels, so the
// thresholds sit a little under what this renderer measures, and the error images are written
// on failure.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "engine/util/image_metrics.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {

const std::string kDir = std::string(RAYFARM_SOURCE_DIR) + "/scenes/pbr_grid/";


/// indirect: RenderSettings::indirectSamples (0: the default split sum); spp: samples per pixel
/// (0: the glTF default, as `still` renders without --spp); bounce: RenderSettings::bounce.
ImageErrorMetrics renderAndCompare(const std::string& name, const SceneOptions& options, const std::string& reference,
                                   double minSsim, double minPsnr, int indirect = 0, int spp = 1,
                                   int bounce = kDefaultBounce) {
    DiskFileSource fs;
    LoadedScene sceneLoaded = loadScene(kDir + "pbr_grid.gltf", fs, options);
    Scene& scene = sceneLoaded.scene;
    useGltfCamera(scene, 0);
    RenderSettings s = scene.settings;
    s.width = 640;
    s.height = 360;
    s.toneMap = ToneMap::Clamp;
    s.exposure = 0.f;
    s.autoExposure = false;
    s.indirectSamples = indirect;
    s.bounce = bounce;
    if (spp > 0) s.spp = spp;
    spp = s.spp;
    RayStats rays;
    const Image img = renderFrame(scene, {scene.camera, s}, 0, 0, rays);
    const std::vector<uint8_t> ours = toRgb8(img, s);
    int w = 0, h = 0;
    const std::vector<uint8_t> ref = readImageRgb8(kDir + "reference/" + reference, w, h);
    EXPECT_EQ(w, 640);
    EXPECT_EQ(h, 360);
    const ImageErrorMetrics e = compareRgb8(ours, ref, w, h);
    std::printf("pbr_grid %s (indirect %d, %d spp) against %s: SSIM %.4f, PSNR %.2f dB\n", name.c_str(), indirect, spp,
                reference.c_str(), e.ssim, e.psnr);
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/pbr_grid";
    std::filesystem::create_directories(out);
    writePng(out + "/" + name + ".png", w, h, ours);
    if (e.ssim < minSsim || e.psnr < minPsnr) {
        writePng(out + "/" + name + "_error.png", w, h, falseColorErrorRgb8(ours, ref, w, h, 0.25));
        ADD_FAILURE() << name << ": SSIM " << e.ssim << " (want >= " << minSsim << "), PSNR " << e.psnr << " dB (want >= "
                      << minPsnr << "); images in " << out;
    }
    return e;
}

}  // namespace

TEST(PbrGrid, LightsOnlyMatchesCycles) {
    // At 1 spp with the default bounce light: measured 0.8975 / 23.14 dB (without bounce light
    // 0.8236 / 19.83 dB; the starting point: 0.29 / 8-11 dB).
    renderAndCompare("lights", SceneOptions{}, "cycles_lights.png", 0.88, 22.5);
}

/// The pbr_grid scene's options with scenes/environments/studio.exr, as Cycles rendered it.
SceneOptions studio() {
    SceneOptions o;
    EnvironmentSpec& e = o.environment.emplace();
    e.file = RAYFARM_SOURCE_DIR "/scenes/environments/studio.exr";
    return o;
}

TEST(PbrGrid, LightsAndStudioMatchCycles) {
    const SceneOptions o = studio();
    // At 1 spp: measured 0.9217 / 24.06 dB (without bounce light 0.8924 / 22.56 dB; the issue's
    // starting point: 0.71 / 8-11 dB).
    renderAndCompare("lights_studio", o, "cycles_lights_studio.png", 0.91, 23.5);
}

// The glTF defaults (4 spp: anti-aliased edges; the split sum and the cached bounce light of
// bounce_cache.h): the aims are SSIM >= 0.90 lights only and >= 0.91 with studio.exr.
TEST(PbrGrid, DefaultSamplesLightsOnly) {
    // Measured 0.9146 / 23.75 dB; without bounce light (--bounce 0) 0.8613 / 20.34 dB.
    renderAndCompare("lights_default_spp", SceneOptions{}, "cycles_lights.png", 0.90, 23.0, 0, 0);
}

TEST(PbrGrid, DefaultSamplesWithStudio) {
    const SceneOptions o = studio();
    // Measured 0.9336 / 24.58 dB; without bounce light 0.9210 / 23.14 dB.
    renderAndCompare("lights_studio_default_spp", o, "cycles_lights_studio.png", 0.91, 24.0, 0, 0);
}

// The bounce light off: what the default was before it (and what --bounce 0 gives).
TEST(PbrGrid, WithoutBounceLightTheUndersidesGoBlack) {
    const ImageErrorMetrics with = renderAndCompare("lights_bounce_default", SceneOptions{}, "cycles_lights.png", 0.90, 23.0, 0, 0);
    const ImageErrorMetrics without =
        renderAndCompare("lights_bounce0", SceneOptions{}, "cycles_lights.png", 0.85, 20.0, 0, 0, 0);
    EXPECT_GT(with.ssim, without.ssim + 0.03) << "the bounce light buys SSIM 0.053 (0.8613 -> 0.9146)";
    EXPECT_GT(with.psnr, without.psnr + 2.5) << "and 3.4 dB (20.34 -> 23.75)";
}

// The quality setting (--indirect N): traced environment occlusion and one diffuse bounce. The
// floor's bounce lights the spheres' undersides, as in Cycles; the default leaves them black.

TEST(PbrGrid, SixteenIndirectSamplesLightsOnly) {
    // Measured 0.8800 / 25.28 dB on 2026-12-05 (0.8618 / 24.87 dB when first written).
    renderAndCompare("lights_indirect16", SceneOptions{}, "cycles_lights.png", 0.85, 24.0, 16);
}

TEST(PbrGrid, SixteenIndirectSamplesWithStudio) {
    // Measured 0.8853 / 23.91 dB (0.8720 / 23.72 dB when first written; one sample a pixel
    // leaves edges aliased and the bounce a little noisy, which SSIM counts).
    renderAndCompare("lights_studio_indirect16", studio(), "cycles_lights_studio.png", 0.86, 23.0, 16);
}

// --spp 4 --indirect 16: the sampled setting that reaches the aim (SSIM >= 0.90) against both,
// at about 15 times the default's time.
TEST(PbrGrid, FourSamplesOfSixteenIndirectLightsOnly) {
    // Measured 0.9210 / 26.83 dB (0.9132 / 26.39 dB when first written).
    renderAndCompare("lights_spp4_indirect16", SceneOptions{}, "cycles_lights.png", 0.90, 25.5, 16, 4);
}

TEST(PbrGrid, FourSamplesOfSixteenIndirectWithStudio) {
    // Measured 0.9206 / 24.60 dB (0.9141 / 24.35 dB when first written).
    renderAndCompare("lights_studio_spp4_indirect16", studio(), "cycles_lights_studio.png", 0.90, 23.5, 16, 4);
}
