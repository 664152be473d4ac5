// The video sweep: real x264 encodes through the MP4 sink, decoded again and scored.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "tests/farm/report/report_test_scene.h"
#include "farm/report/report_video.h"
#include "farm/output/video_decode.h"

namespace rf::report {
namespace {

/// Frames of the edge scene with the camera sliding sideways, so the encoder sees motion.
std::vector<std::vector<uint8_t>> movingFrames(int n, int w, int h) {
    Scene sc = testing::edgeScene(false);
    RenderSettings s = sc.settings;
    s.width = w;
    s.height = h;
    std::vector<std::vector<uint8_t>> out;
    for (int i = 0; i < n; ++i) {
        sc.camera.eye.x = 0.1f * i;
        RayStats rays;
        out.push_back(toRgb8(renderFrame(sc, {sc.camera, s}, i, 2, rays), s.toneMap));
    }
    return out;
}

TEST(ReportVideo, LosslessDecodesExactlyAndHigherCrfLosesMore) {
    const int w = 64, h = 48;
    const auto frames = movingFrames(5, w, h);
    VideoSweepSpec spec;
    spec.crf = {12, 40};
    spec.presets = {"ultrafast", "medium"};
    const std::string scratch = testing::freshDir("report_video") + "/scratch.mp4";
    const auto rows = runVideoSweep(frames, w, h, spec, scratch);
    ASSERT_EQ(rows.size(), 1u + 2 * 2);
    EXPECT_TRUE(rows[0].lossless);
    EXPECT_TRUE(std::isinf(rows[0].psnr)) << rows[0].psnr;
    EXPECT_DOUBLE_EQ(rows[0].ssim, 1.0);
    EXPECT_FALSE(rows[0].pareto);
    for (size_t i = 1; i < rows.size(); ++i) {
        EXPECT_EQ(rows[i].frames, 5);
        EXPECT_GT(rows[i].bytes, 0u);
        EXPECT_TRUE(std::isfinite(rows[i].psnr));
        EXPECT_LE(rows[i].minPsnr, rows[i].psnr + 1e-9);  // pooled PSNR is at least the worst frame's
    }
    // Rows are preset-major: [ultrafast 12, ultrafast 40, medium 12, medium 40].
    EXPECT_GT(rows[1].psnr, rows[2].psnr + 3.0);
    EXPECT_GT(rows[3].psnr, rows[4].psnr + 3.0);
    EXPECT_GT(rows[1].psnr, 35.0);  // CRF 12 is near transparent on a clean render
    EXPECT_FALSE(std::filesystem::exists(scratch));
}

TEST(ReportVideo, OddSizesAreCroppedBackAfterDecoding) {
    const int w = 33, h = 17;
    const auto frames = movingFrames(2, w, h);
    VideoSweepSpec spec;
    spec.crf = {18};
    spec.presets = {"ultrafast"};
    spec.losslessCheck = false;
    const auto rows = runVideoSweep(frames, w, h, spec, testing::freshDir("report_video_odd") + "/odd.mp4");
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].frames, 2);
    EXPECT_GT(rows[0].psnr, 25.0);  // a misaligned crop would score far lower
}

TEST(ReportVideo, DecodingAMissingFileNamesIt) {
    try {
        farm::decodeVideoRgb8("/nonexistent/x.mp4", 8, 8);
        FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/x.mp4"), std::string::npos);
    }
}

VideoRow vrow(double fps, double psnr, bool lossless = false) {
    VideoRow r;
    r.encodeFps = fps;
    r.psnr = psnr;
    r.lossless = lossless;
    return r;
}

TEST(ReportVideo, ParetoPrefersFasterAndSharperAndIgnoresLossless) {
    std::vector<VideoRow> rows = {vrow(100, 40), vrow(200, 35), vrow(150, 34), vrow(50, 41),
                                  vrow(10, INFINITY, true)};
    markVideoPareto(rows);
    const bool expect[] = {true, true, false, true, false};
    for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i].pareto, expect[i]) << i;
}

}  // namespace
}  // namespace rf::report
