// The default sampling of a bare glTF turntable shows no crawling edges: a frame of
// 2CylinderEngine's film at the default samples is close to a 64-sample render of the same
// frame, where one sample a pixel (the fins' moiré) is not. Both are measured, so the test shows
// it tells the two apart.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "engine/lights/exposure.h"
#include "engine/util/file_source.h"
#include "engine/util/image_metrics.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::anim {
namespace {

/// Measured at 320×180: default (4 spp) 34.55 dB, 1 spp 28.50 dB against 64 spp.
constexpr double kMinPsnr = 33.0;
const std::string kEngine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

/// One frame of the posed scene at `spp`, as 8-bit sRGB through the film's tone map and EV.
/// bounce: the film's bounce cache.
std::vector<uint8_t> frameAt(const Scene& s, RenderSettings rs, int frame, int spp,
                             const std::shared_ptr<SceneCacheSlot>& bounce) {
    rs.spp = spp;
    RayStats st;
    return toRgb8(renderFrame(s, {s.camera, rs, bounce}, frame, 0, st), rs);
}

TEST(DefaultTurntableSampling, EngineFinsDoNotAliasAtTheDefaultSamples) {
    if (!std::filesystem::exists(kEngine)) GTEST_FAIL() << kEngine << " missing (package assimp-testmodels)";
    DiskFileSource fs;
    SceneOptions opts;
    opts.width = 320;
    opts.height = 180;
    LoadedScene sLoaded = loadScene(kEngine, fs, opts);
    Scene& s = sLoaded.scene;
    ASSERT_EQ(s.settings.spp, 4) << "the glTF default";
    const Timeline tl = Timeline::fromScene(sLoaded);
    const int frame = 10;  // the fins run across the picture, a few pixels apart
    tl.applyFrame(s, frame);
    RenderSettings rs = s.settings;
    // One EV for every render of the frame, as auto exposure gives a film.
    RenderSettings meterSettings = rs;
    meterSettings.spp = 1;
    RayStats st;
    ExposureMeter meter;
    const auto bounce = std::make_shared<SceneCacheSlot>();  // the film's bounce cache, as a render job keeps it
    meter.add(renderFrame(s, {s.camera, meterSettings, bounce}, frame, 0, st));
    rs.exposure = meter.ev();
    rs.autoExposure = false;

    const std::vector<uint8_t> reference = frameAt(s, rs, frame, 64, bounce);
    const ImageErrorMetrics byDefault = compareRgb8(frameAt(s, rs, frame, s.settings.spp, bounce), reference, 320, 180);
    const ImageErrorMetrics oneSample = compareRgb8(frameAt(s, rs, frame, 1, bounce), reference, 320, 180);
    std::printf("2CylinderEngine frame %d at 320x180 against 64 spp: default %.2f dB / SSIM %.4f, 1 spp %.2f dB / %.4f\n",
                frame, byDefault.psnr, byDefault.ssim, oneSample.psnr, oneSample.ssim);
    EXPECT_GE(byDefault.psnr, kMinPsnr);
    EXPECT_LT(oneSample.psnr, kMinPsnr) << "the threshold no longer tells aliasing apart";
}

}  // namespace
}  // namespace rf::anim
