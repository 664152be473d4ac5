// The outputs beside the video: the pixel layout with alpha and the linear plane through the
// messages and the assembler, EXR frames against the engine's framebuffer, the contact sheet's
// grid and labels, the poster, and which format/option combinations are refused.
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <array>
#include <cstring>
#include <filesystem>

#include "farm/output/bitmap_font.h"
#include "farm/output/contact_sheet.h"
#include "farm/output/exr_frames.h"
#include "tests/farm/farm_test_scene.h"
#include "farm/cluster/frame_assembler.h"
#include "engine/util/image.h"
#include "farm/cluster/messages.h"
#include "engine/integrators/render.h"
#include "farm/cluster/render_engine.h"
#include "anim/timeline.h"
#include "farm/output/video_format.h"

using namespace rf;
using namespace rf::farm;

namespace {

std::string outDir(const std::string& name) {
    const std::string d = std::string(RAYFARM_TEST_OUT) + "/farm_outputs/" + name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

LoadedScene transparentFarmScene() {
    LoadedScene loaded = rf::testing::loadFarmScene();
    Scene& s = loaded.scene;
    s.transparentBackground = true;
    s.geometry.planes.clear();  // no floor: sky around the spheres
    s.build();
    return loaded;
}

/// Frame `frame` through the farm's path: RenderEngine::render on tiles of 16, assembled.
std::vector<uint8_t> farmFrame(LoadedScene& loaded, const RenderSettings& rs, int frame, PixelLayout layout) {
    Scene& scene = loaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    FrameAssembler a(rs.width, rs.height, {frame}, {}, layout);
    int applied = -1;
    for (const TileRect& t : makeTiles(rs.width, rs.height, 16)) {
        const TileResult r = RenderEngine::render(scene, tl, rs, 2, {frame, t}, applied, layout.linear);
        EXPECT_EQ(r.layout, layout);
        a.add(decodeTileResult(encodeTileResult(r)));  // through the wire format too
    }
    ReadyFrame out;
    EXPECT_TRUE(a.popReady(out));
    return out.rgb;
}

}  // namespace

TEST(Outputs, ResultsWithAlphaAndLinearPlaneRoundTrip) {
    TileResult r;
    r.item = {3, {0, 0, 3, 2}};
    r.layout = {4, true};
    r.rgb.resize(r.layout.bytes(6));
    for (size_t i = 0; i < r.rgb.size(); ++i) r.rgb[i] = uint8_t(i * 13);
    const TileResult back = decodeTileResult(encodeTileResult(r));
    EXPECT_EQ(back.layout, r.layout);
    EXPECT_EQ(back.rgb, r.rgb);
    // The same bytes claimed as RGB without a linear plane do not add up.
    std::string bytes = encodeTileResult(r);
    r.layout = {3, false};
    r.rgb.resize(r.layout.bytes(6));
    EXPECT_THROW(decodeTileResult(encodeTileResult(r) + std::string(10, 'x')), std::runtime_error);
    bytes[20] = 7;  // the layout field: 7 channels
    EXPECT_THROW(decodeTileResult(bytes), std::runtime_error);
}

TEST(Outputs, AssemblerRefusesAnotherLayout) {
    FrameAssembler a(4, 4, {0}, {}, PixelLayout{4, false});
    TileResult r;
    r.item = {0, {0, 0, 4, 4}};
    r.layout = {3, false};
    r.rgb.resize(r.layout.bytes(16));
    EXPECT_THROW(a.add(r), std::runtime_error);
}

// The farm's frame (tiles, wire, assembler) equals the engine's renderFrame: 8-bit straight RGBA
// from toRgba8, and the linear plane bit for bit; written as EXR it reads back equal to half
// precision (rounding to nearest: relative error ≤ 2^-11).
TEST(Outputs, ExrFramesHoldTheLinearFramebufferToHalfPrecision) {
    LoadedScene scene = transparentFarmScene();
    RenderSettings rs = scene.scene.settings;
    rs.width = 48;
    rs.height = 36;
    rs.spp = 4;
    const PixelLayout layout{4, true};
    const std::vector<uint8_t> frame = farmFrame(scene, rs, 2, layout);

    LoadedScene refLoaded = transparentFarmScene();
    Scene& ref = refLoaded.scene;
    anim::Timeline::fromScene(refLoaded).applyFrame(ref, 2);
    RayStats st;
    const Image img = renderFrame(ref, {ref.camera, rs}, 2, 2, st);
    const size_t n = size_t(rs.width) * rs.height;
    const std::vector<uint8_t> rgba8 = toRgba8(img, rs.toneMap);
    ASSERT_EQ(std::memcmp(frame.data(), rgba8.data(), n * 4), 0);
    std::vector<float> linear(n * 4);
    std::memcpy(linear.data(), frame.data() + layout.linearOffset(n), linear.size() * sizeof(float));
    int transparent = 0, opaque = 0;
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(linear[4 * i + c], img.data()[3 * i + c]);
        ASSERT_EQ(linear[4 * i + 3], img.alpha()[i]);
        transparent += img.alpha()[i] == 0.f;
        opaque += img.alpha()[i] == 1.f;
    }
    EXPECT_GT(transparent, 100);
    EXPECT_GT(opaque, 100);

    const std::string dir = outDir("exr");
    ExrSink sink(dir, rs.width, rs.height, layout);
    sink.write(2, frame);
    int w = 0, h = 0;
    const std::vector<float> back = readExrRgba(frameExrPath(dir, 2), w, h);
    ASSERT_EQ(w, rs.width);
    ASSERT_EQ(h, rs.height);
    for (size_t i = 0; i < n * 4; ++i) {
        const float want = linear[i];
        ASSERT_EQ(back[i], float(Imath::half(want))) << "value " << i;  // exactly the half nearest the float
        ASSERT_LE(std::abs(back[i] - want), std::abs(want) * (1.f / 2048.f) + 6e-8f) << "value " << i;
    }
    EXPECT_EQ(findKeptExrFrames(dir, {1, 2}, rs.width, rs.height), anim::FrameRanges{2});
    EXPECT_TRUE(findKeptExrFrames(dir, {2}, rs.width + 1, rs.height).empty());
}

TEST(Outputs, ContactSheetPlanSpacesFramesEvenly) {
    const ContactSheetPlan p = planContactSheet(0, 119, 640, 360);
    EXPECT_EQ(p.frames, (std::vector<int>{0, 11, 22, 32, 43, 54, 65, 76, 87, 97, 108, 119}));
    EXPECT_EQ(p.cols, 4);
    EXPECT_EQ(p.rows, 3);
    EXPECT_EQ(p.thumbW, 160);
    EXPECT_EQ(p.thumbH, 90);
    EXPECT_EQ(p.sheetW, p.pad + 4 * (160 + p.pad));
    const ContactSheetPlan small = planContactSheet(5, 7, 64, 48);
    EXPECT_EQ(small.frames, (std::vector<int>{5, 6, 7}));
    EXPECT_EQ(small.cols, 3);
    EXPECT_EQ(small.thumbW, 64);  // small films keep full-size thumbnails
    EXPECT_EQ(frameLabel(12, 0.4), "#12 0.40s");
}

// The sheet as written: its size is the plan's, each received frame's cell holds its thumbnail
// and exactly the label's pixels, and a frame that never came leaves its cell empty.
TEST(Outputs, ContactSheetHoldsLabelledThumbnailsOfFinishedFramesOnly) {
    const int w = 64, h = 48;
    const std::string path = outDir("sheet") + "/sheet.png";
    ContactSheetSink sink(path, w, h, 3, 0, 9, [](int f) { return f / 30.0; });
    const ContactSheetPlan plan = sink.plan();
    ASSERT_EQ(plan.frames.size(), 10u);
    for (int f = 0; f <= 6; ++f) {  // frames 7-9 never finish
        std::vector<uint8_t> rgb(size_t(w) * h * 3);
        for (size_t i = 0; i < rgb.size(); i += 3) rgb[i] = uint8_t(20 * f), rgb[i + 1] = 200, rgb[i + 2] = 100;
        sink.write(f, rgb);
    }
    sink.close();
    int sw = 0, sh = 0;
    const std::vector<uint8_t> sheet = readImageRgb8(path, sw, sh);
    ASSERT_EQ(sw, plan.sheetW);
    ASSERT_EQ(sh, plan.sheetH);
    for (size_t k = 0; k < plan.frames.size(); ++k) {
        const int f = plan.frames[k];
        const int cx = plan.pad + int(k % plan.cols) * (plan.thumbW + plan.pad);
        const int cy = plan.pad + int(k / plan.cols) * (plan.cellH + plan.pad);
        const uint8_t* mid = &sheet[3 * (size_t(cy + plan.thumbH / 2) * sw + cx + plan.thumbW / 2)];
        // The label strip as it should be: the sheet's grey with the label drawn in.
        std::vector<uint8_t> want(size_t(sw) * sh * 3, 48);
        if (f <= 6) drawText(want, sw, sh, cx, cy + plan.thumbH + plan.pad / 2, frameLabel(f, f / 30.0), plan.labelScale,
                             std::array<uint8_t, 3>{235, 235, 235}.data());
        for (int y = cy + plan.thumbH; y < cy + plan.cellH; ++y)
            for (int x = cx; x < cx + plan.thumbW; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(sheet[3 * (size_t(y) * sw + x) + c], want[3 * (size_t(y) * sw + x) + c])
                        << "frame " << f << " label pixel " << x << "," << y;
        if (f <= 6) {
            EXPECT_EQ(mid[0], 20 * f);
            EXPECT_EQ(mid[1], 200);
        } else {
            EXPECT_EQ(mid[0], 48) << "frame " << f << " never finished but has a thumbnail";
            EXPECT_EQ(mid[1], 48);
        }
    }
}

TEST(Outputs, PosterIsTheChosenFrameAtFullSize) {
    const std::string path = outDir("poster") + "/poster.png";
    PosterSink sink(path, 4, 8, 6, 4);
    std::vector<uint8_t> rgba(8 * 6 * 4);
    for (int f = 3; f <= 5; ++f) {
        for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(f * 10 + i % 4);
        sink.write(f, rgba);
    }
    int w = 0, h = 0;
    const std::vector<uint8_t> back = readImage8(path, w, h, 4);
    EXPECT_EQ(w, 8);
    EXPECT_EQ(h, 6);
    EXPECT_EQ(back[0], 40);
    EXPECT_EQ(back[3], 43);  // alpha kept
}

// Unsupported combinations are refused by videoFormatFor before anything renders.
TEST(Outputs, VideoFormatFollowsTheNameAndRefusesWhatItCannotDo) {
    auto fmt = [](const std::string& path, const std::string& codec = "", int crf = -1, const std::string& preset = "",
                  bool lossless = false, bool alpha = false) {
        return videoFormatFor(VideoRequest{path, codec, crf, preset, lossless, alpha});
    };
    EXPECT_EQ(fmt("a.mp4").encoder, "libx264");
    EXPECT_EQ(fmt("a.webm", "", -1, "", false, true).pixFmt, "yuva420p");
    EXPECT_EQ(fmt("a.webm").pixFmt, "yuv420p");
    EXPECT_EQ(fmt("a.MOV", "", -1, "", false, true).pixFmt, "yuva444p10le");
    EXPECT_EQ(fmt("a.gif").encoder, "gif");
    EXPECT_EQ(fmt("a.webm", "", -1, "ultrafast").encoderOptions[0], (std::pair<std::string, std::string>{"cpu-used", "8"}));
    EXPECT_THROW(fmt("a.avi"), std::invalid_argument);
    EXPECT_THROW(fmt("a.mp4", "vp9"), std::invalid_argument);
    EXPECT_THROW(fmt("a.webm", "h264"), std::invalid_argument);
    EXPECT_THROW(fmt("a.mp4", "", 60), std::invalid_argument);
    EXPECT_NO_THROW(fmt("a.webm", "", 60));
    EXPECT_THROW(fmt("a.webm", "", 64), std::invalid_argument);
    EXPECT_THROW(fmt("a.mov", "", 20), std::invalid_argument);
    EXPECT_THROW(fmt("a.mov", "", -1, "", true), std::invalid_argument);
    EXPECT_THROW(fmt("a.mov", "", -1, "hq", false, true), std::invalid_argument);
    EXPECT_NO_THROW(fmt("a.mov", "", -1, "hq"));
    EXPECT_THROW(fmt("a.gif", "", 20), std::invalid_argument);
    EXPECT_THROW(fmt("a.gif", "", -1, "", true), std::invalid_argument);
    EXPECT_THROW(fmt("a.gif", "", -1, "veryfast"), std::invalid_argument);
}
