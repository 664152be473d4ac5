#pragma once
// Scoring an animated render against Blender Cycles at one animation time, shared by
// skinned_cycles_test.cpp and file_camera_cycles_test.cpp: both render a transparent background
// (alpha = coverage) and score the model's pixels, not the background: the pose by the IoU of the
// two coverage masks (alpha > 1/2), the picture by SSIM over the windows centred on covered pixels
// (both laid over black). Each also scores the other time's reference, which must fail: the
// thresholds tell one time from another. Images and error images are written on failure.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/integrators/render.h"
#include "engine/util/image.h"
#include "engine/util/image_metrics.h"

namespace rf::cyclestest {

struct Rgba {
    int w = 0, h = 0;
    std::vector<uint8_t> px;  ///< straight RGBA
};

/// The scene through its camera at w×h over a transparent background, as `still --background
/// transparent --exposure 0 --tonemap clamp --spp 16` renders it (Cycles' edges are anti-aliased
/// over many samples; so must ours be).
inline Rgba renderTransparent(Scene& scene, int w, int h) {
    scene.transparentBackground = true;
    RenderSettings s = scene.settings;
    s.width = w;
    s.height = h;
    s.spp = 16;
    s.toneMap = ToneMap::Clamp;
    s.exposure = 0.f;
    s.autoExposure = false;
    RayStats rays;
    return {w, h, toRgba8(renderFrame(scene, {scene.camera, s}, 0, 0, rays), s.toneMap, 1.f)};
}

inline Rgba readReference(const std::string& path) {
    Rgba r;
    r.px = readImage8(path, r.w, r.h, 4);
    return r;
}

struct Score {
    double iou = 0.0, ssim = 0.0;
};

/// Over black, premultiplied, 8-bit RGB.
inline std::vector<uint8_t> overBlack(const Rgba& img) {
    std::vector<uint8_t> out(size_t(img.w) * img.h * 3);
    for (size_t i = 0; i < size_t(img.w) * img.h; ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = uint8_t((int(img.px[4 * i + c]) * img.px[4 * i + 3] + 127) / 255);
    return out;
}

inline Score score(const Rgba& ours, const Rgba& ref) {
    size_t both = 0, either = 0;
    std::vector<uint8_t> m(size_t(ref.w) * ref.h, 0);
    for (size_t i = 0; i < m.size(); ++i) {
        const bool a = ours.px[4 * i + 3] > 127, b = ref.px[4 * i + 3] > 127;
        both += a && b;
        either += a || b;
        m[i] = a || b;
    }
    Score s;
    s.iou = either ? double(both) / double(either) : 0.0;
    s.ssim = ssimRgb8Masked(overBlack(ours), overBlack(ref), ref.w, ref.h, m);
    return s;
}

/// Scores `ours` (what was rendered at time t) against `ref` (thresholds `want`) and against
/// `other` (the reference at otherT), which must fall below at least one of them. `what` names
/// it in messages; the images go to RAYFARM_TEST_OUT/outDir/base(.png, _error.png).
inline void checkTime(const std::string& what, const Rgba& ours, const Rgba& ref, const Rgba& other, double t, double otherT,
                      Score want, const std::string& outDir, const std::string& base) {
    const Score s = score(ours, ref), wrong = score(ours, other);
    std::printf("%s at %.2f s against Cycles: coverage IoU %.4f, SSIM %.4f (against the %.2f s reference: IoU %.4f, "
                "SSIM %.4f)\n",
                what.c_str(), t, s.iou, s.ssim, otherT, wrong.iou, wrong.ssim);
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/" + outDir;
    std::filesystem::create_directories(out);
    writePng(out + "/" + base + ".png", ours.w, ours.h, ours.px, 4);
    if (s.iou < want.iou || s.ssim < want.ssim) {
        writePng(out + "/" + base + "_error.png", ref.w, ref.h, falseColorErrorRgb8(overBlack(ours), overBlack(ref), ref.w, ref.h, 0.25));
        ADD_FAILURE() << what << " at " << t << " s: IoU " << s.iou << " (want >= " << want.iou << "), SSIM " << s.ssim
                      << " (want >= " << want.ssim << "); images in " << out;
    }
    EXPECT_TRUE(wrong.iou < want.iou || wrong.ssim < want.ssim)
        << what << ": the " << otherT << " s reference passes too (IoU " << wrong.iou << ", SSIM " << wrong.ssim
        << "): the thresholds do not tell the two times apart";
}

}  // namespace rf::cyclestest
