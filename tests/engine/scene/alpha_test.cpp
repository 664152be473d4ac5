// Coverage alpha from renderTile: the fraction of a pixel's samples whose primary ray meets
// geometry, checked against the analytic silhouette of a sphere; premultiplied colour; the
// straight 8-bit conversion for PNG.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/engine/engine_test_util.h"

using namespace rf;

namespace {

// A unit sphere 6 units in front of the camera, lit, on an opaque red background.
Scene sphereScene() {
    Scene s = test::emptyScene();
    s.materials = {test::matte(Color(0.2f, 0.6f, 0.9f))};
    s.geometry.spheres.push_back(Sphere{Vec3(0.f), 1.f, 0});
    Light l;
    l.position = Vec3(3, 5, 5);
    s.lights.push_back(l);
    s.camera.eye = Vec3(0, 0, 6);
    s.camera.fovDeg = 30.f;
    s.background = Color(0.8f, 0.1f, 0.1f);
    s.build();
    return s;
}

}  // namespace

// The silhouette of a sphere of radius R seen from distance D is a circle of angular radius
// asin(R/D): on the image plane of focal length f (pixels) a disc of radius f·tan(asin(R/D)).
// Summed coverage is its area; with 16 stratified samples a pixel the edge error averages out
// far below 1%.
TEST(Alpha, SummedCoverageIsTheSilhouetteArea) {
    Scene s = sphereScene();
    s.transparentBackground = true;
    const RenderSettings rs = test::smallSettings(120, 120, 16);
    RayStats st;
    const Image img = renderFrame(s, {s.camera, rs}, 0, 2, st);
    ASSERT_TRUE(img.hasAlpha());
    double sum = 0.0;
    int partial = 0;
    for (float a : img.alpha()) {
        ASSERT_GE(a, 0.f);
        ASSERT_LE(a, 1.f);
        sum += a;
        partial += a > 0.f && a < 1.f;
    }
    const double f = 60.0 / std::tan(15.0 * M_PI / 180.0);
    const double r = f * std::tan(std::asin(1.0 / 6.0));
    EXPECT_NEAR(sum, M_PI * r * r, 0.005 * M_PI * r * r);
    EXPECT_GT(partial, int(2 * M_PI * r * 0.7));  // the anti-aliased edge is fractional all round
    EXPECT_EQ(img.alpha()[0], 0.f);                       // a corner sees only background
    EXPECT_EQ(img.alpha()[60 * 120 + 60], 1.f);           // the centre only sphere
}

// Misses add no colour: the transparent render's colour equals an opaque render over black,
// bit for bit (premultiplied), and where coverage is full it equals the render over red.
TEST(Alpha, ColourIsPremultipliedByCoverage) {
    Scene s = sphereScene();
    const RenderSettings rs = test::smallSettings(64, 48, 4);
    RayStats st;
    const Image overRed = renderFrame(s, {s.camera, rs}, 3, 2, st);
    s.background = Color(0.f);
    const Image overBlack = renderFrame(s, {s.camera, rs}, 3, 2, st);
    s.background = Color(0.8f, 0.1f, 0.1f);
    s.transparentBackground = true;
    const Image clear = renderFrame(s, {s.camera, rs}, 3, 2, st);
    ASSERT_FALSE(overBlack.hasAlpha());
    int full = 0;
    for (int i = 0; i < 64 * 48; ++i) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(clear.data()[3 * i + c], overBlack.data()[3 * i + c]) << "pixel " << i;
        if (clear.alpha()[i] == 1.f) {
            ++full;
            for (int c = 0; c < 3; ++c) ASSERT_EQ(clear.data()[3 * i + c], overRed.data()[3 * i + c]);
        }
    }
    EXPECT_GT(full, 100);
}

// renderTile's optional alpha output agrees with the frame's alpha plane.
TEST(Alpha, RenderTileWritesCoverageForItsRectangle) {
    Scene s = sphereScene();
    s.transparentBackground = true;
    const RenderSettings rs = test::smallSettings(50, 40, 4);
    RayStats st;
    const Image frame = renderFrame(s, {s.camera, rs}, 1, 1, st);
    const TileRect rect{10, 8, 37, 30};
    std::vector<float> rgb(size_t(rect.pixels()) * 3), alpha(size_t(rect.pixels()), -1.f);
    renderTile(s, {s.camera, rs}, rect, 1, rgb.data(), st, alpha.data());
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x)
            ASSERT_EQ(alpha[size_t(y - rect.y0) * rect.width() + (x - rect.x0)], frame.alpha()[size_t(y) * 50 + x]);
}

// Straight alpha for PNG: the colour is un-premultiplied before tone mapping and encoding, so
// a half-covered pixel keeps the surface's colour; zero coverage gives transparent black.
TEST(Alpha, EightBitConversionIsStraightAlpha) {
    uint8_t out[4];
    const float half[3] = {0.25f, 0.1f, 0.f};  // premultiplied by 0.5: the surface is (0.5, 0.2, 0)
    toRgba8Pixel(half, 0.5f, ToneMap::Clamp, out);
    EXPECT_EQ(out[0], toByte(srgbEncode(0.5f)));
    EXPECT_EQ(out[1], toByte(srgbEncode(0.2f)));
    EXPECT_EQ(out[2], 0);
    EXPECT_EQ(out[3], 128);
    const float none[3] = {0.f, 0.f, 0.f};
    toRgba8Pixel(none, 0.f, ToneMap::Clamp, out);
    EXPECT_EQ(out[0] | out[1] | out[2] | out[3], 0);
    const float full[3] = {0.18f, 0.5f, 2.f};
    toRgba8Pixel(full, 1.f, ToneMap::Clamp, out);
    EXPECT_EQ(out[0], 118);  // catalogue 31
    EXPECT_EQ(out[1], 188);
    EXPECT_EQ(out[2], 255);
    EXPECT_EQ(out[3], 255);
}
