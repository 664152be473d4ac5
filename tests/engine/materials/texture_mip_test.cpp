// Texture filtering by footprint: mip levels average what they halve, a lookup whose footprint
// covers no more than a texel reads exactly the unfiltered texture, and, rendered, a checker
// seen from afar reads as its average (close to a 64-spp render of it) while a near one stays
// sharp, bit for bit the unfiltered picture.
#include <gtest/gtest.h>

#include "tests/engine/engine_test_util.h"
#include "engine/materials/material_eval.h"

namespace rf {
namespace {

/// An n×n checker of one-texel cells, black and white, repeating.
Texture checker(int n) {
    Texture t;
    t.width = t.height = n;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) t.texels.push_back(Vec4(Vec3(float((x + y) & 1)), 1.f));
    buildMipmaps(t);
    return t;
}

/// A 2×2 floor at y = 0 whose texture coordinates repeat the 8×8 checker `repeat` times across,
/// lit only by ambient light 1 (the pixel is the texel), seen from 2.5 above.
Scene checkerFloor(float repeat, bool mips) {
    Scene s = test::emptyScene();
    TriangleMesh m = test::gridMesh(4, 1.f, 0);
    for (const Vec3& p : m.positions) m.uvs.emplace_back(repeat * (p.x + 1.f) / 2.f, repeat * (p.z + 1.f) / 2.f);
    s.geometry.meshes.push_back(m);
    Texture t = checker(8);
    if (!mips) t.mips.clear();
    s.textures.push_back(std::move(t));
    Material& mat = s.materials[0] = test::matte(Color(1.f), 1.f, 0.f);
    mat.baseColorTexture = 0;
    s.ambientLight = Color(1.f);
    s.camera.eye = Vec3(0.f, 2.5f, 0.f);
    s.camera.target = Vec3(0.f);
    s.camera.up = Vec3(0.f, 0.f, -1.f);
    s.camera.fovDeg = 30.f;
    s.build();
    return s;
}

/// PSNR of a against b (red channel, linear values in [0, 1]).
double psnr(const Image& a, const Image& b) {
    double se = 0.0;
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const double d = double(a.pixel(x, y)[0]) - double(b.pixel(x, y)[0]);
            se += d * d;
        }
    const double mse = se / (double(a.width()) * a.height());
    return mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : 200.0;
}

}  // namespace

TEST(TextureMips, LevelsAverageWhatTheyHalveDownToOneTexel) {
    const Texture t = checker(8);
    ASSERT_EQ(t.mips.size(), 3u);  // 4×4, 2×2, 1×1
    EXPECT_EQ(t.mips[0].width, 4);
    EXPECT_EQ(t.mips.back().width, 1);
    for (const TextureLevel& l : t.mips)
        for (const Vec4& v : l.texels) EXPECT_FLOAT_EQ(v.r, 0.5f);
    Texture odd;
    odd.width = 3;
    odd.height = 1;
    odd.texels = {Vec4(0.f), Vec4(1.f), Vec4(0.5f)};
    buildMipmaps(odd);
    ASSERT_EQ(odd.mips.size(), 2u);  // 2×1 (the odd column kept alone), 1×1
    EXPECT_FLOAT_EQ(odd.mips[0].texels[0].r, 0.5f);
    EXPECT_FLOAT_EQ(odd.mips[0].texels[1].r, 0.5f);
}

TEST(TextureMips, AFootprintWithinATexelReadsTheUnfilteredTexture) {
    const Texture t = checker(8);
    for (float u : {0.03f, 0.27f, 0.61f, 0.94f}) {
        const Vec2 uv(u, 1.f - u);
        EXPECT_EQ(sampleTexture(t, uv, 0.f), sampleTexture(t, uv));
        EXPECT_EQ(sampleTexture(t, uv, 0.9f / 64.f), sampleTexture(t, uv));  // under one texel
        EXPECT_FLOAT_EQ(sampleTexture(t, uv, 4.f / 64.f).r, 0.5f);              // two texels across
        EXPECT_FLOAT_EQ(sampleTexture(t, uv, 100.f).r, 0.5f);                   // far beyond: the mean
    }
}

TEST(TextureMips, AFarCheckerReadsAsItsAverageAndMatchesSupersampling) {
    // 64 repeats of 8 texels over 2 units, seen from 2.5 at 30° on 64 pixels: about 6 texels a
    // pixel. Unfiltered, each pixel picks one texel (0 or 1): the moiré that crawls in a turntable.
    const RenderSettings one = test::smallSettings(64, 64, 1);
    const RenderSettings many = test::smallSettings(64, 64, 64);
    const Image reference = test::render(checkerFloor(64.f, true), many);
    const Image filtered = test::render(checkerFloor(64.f, true), one);
    const Image unfiltered = test::render(checkerFloor(64.f, false), one);
    double worst = 0.0;
    for (int y = 16; y < 48; ++y)
        for (int x = 16; x < 48; ++x) worst = std::max(worst, std::abs(double(filtered.pixel(x, y)[0]) - 0.5));
    EXPECT_LT(worst, 0.02) << "a far pixel strays from the checker's average";
    const double p = psnr(filtered, reference), pu = psnr(unfiltered, reference);
    std::printf("far checker, 1 spp against 64 spp: filtered %.1f dB, unfiltered %.1f dB\n", p, pu);
    EXPECT_GT(p, 25.0);
    EXPECT_GT(p, pu + 10.0) << "the unfiltered picture should alias (else this test cannot fail)";
}

TEST(TextureMips, ANearCheckerStaysSharp) {
    // One repeat: 8 texels over 2 units, some 12 pixels a texel; the footprint is under a texel, so
    // the picture is the unfiltered one exactly, black and white at (bilinear) full contrast:
    // some pixel lands within 1/24 texel of a texel's centre, where the bilinear ramp of a
    // one-texel checker is within about 0.1 of the texel; averaged, every pixel would read 0.5.
    const RenderSettings one = test::smallSettings(64, 64, 1);
    const Image filtered = test::render(checkerFloor(1.f, true), one);
    const Image unfiltered = test::render(checkerFloor(1.f, false), one);
    float lo = 1.f, hi = 0.f;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            EXPECT_EQ(filtered.pixel(x, y)[0], unfiltered.pixel(x, y)[0]) << x << "," << y;
            lo = std::min(lo, filtered.pixel(x, y)[0]);
            hi = std::max(hi, filtered.pixel(x, y)[0]);
        }
    EXPECT_LT(lo, 0.1f);
    EXPECT_GT(hi, 0.9f);
}

TEST(TextureSet, CopiesOfASceneShareTheirTexturesUntilOneAddsAnother) {
    // The auto-exposure probe copies the scene: the texels must not be copied with it.
    Scene a = test::emptyScene();
    a.textures.push_back(checker(8));
    const Scene b = a;
    EXPECT_TRUE(a.textures.sharedWith(b.textures));
    EXPECT_EQ(&a.textures[0], &b.textures[0]);
    // Adding to one copy leaves the other as it was.
    a.textures.push_back(checker(4));
    EXPECT_FALSE(a.textures.sharedWith(b.textures));
    EXPECT_EQ(a.textures.size(), 2u);
    EXPECT_EQ(b.textures.size(), 1u);
    EXPECT_EQ(b.textures[0].width, 8);
}

}  // namespace rf
