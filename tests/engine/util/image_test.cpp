// sRGB encoding, float → byte conversion and tone mapping (catalogue 31–33), PNG round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "engine/util/image.h"

using namespace rf;

TEST(Image, SrgbEncodeKnownValues) {
    EXPECT_NEAR(srgbEncode(0.5f), 0.7354f, 1e-4f);
    EXPECT_EQ(toByte(srgbEncode(0.5f)), 188);
    EXPECT_NEAR(srgbEncode(0.18f), 0.4614f, 1e-4f);
    EXPECT_EQ(toByte(srgbEncode(0.18f)), 118);
    EXPECT_EQ(srgbEncode(0.f), 0.f);
    EXPECT_EQ(srgbEncode(1.f), 1.f);
    EXPECT_EQ(srgbEncode(std::nanf("")), 0.f);
}

TEST(Image, SrgbBranchesMeetAtTheThreshold) {
    const float x = 0.0031308f;
    const float lin = 12.92f * x, pw = 1.055f * std::pow(x, 1.f / 2.4f) - 0.055f;
    EXPECT_NEAR(lin, 0.04045f, 1e-5f);
    EXPECT_NEAR(pw, lin, 1e-5f);
    EXPECT_NEAR(srgbEncode(std::nextafter(x, 0.f)), srgbEncode(std::nextafter(x, 1.f)), 1e-5f);
    for (float v : {0.001f, 0.0031308f, 0.01f, 0.2f, 0.5f, 0.9f}) EXPECT_NEAR(srgbDecode(srgbEncode(v)), v, 1e-5f * std::max(1.f, v / 0.01f));
}

// srgbByte's threshold table gives toByte(srgbEncode(v)) for every float: every 61st bit pattern
// of [0, 1] (17 million of them), the four floats either side of each of the 255 steps, and the
// values outside [0, 1]. (Every float of [0, 1], 1.07 billion, was checked once by hand.)
TEST(Image, SrgbByteMatchesTheFunctionItTabulates) {
    int mismatches = 0;
    auto check = [&](float v) {
        if (srgbByte(v) != toByte(srgbEncode(v)) && ++mismatches <= 5)
            ADD_FAILURE() << "v = " << v << ": srgbByte " << int(srgbByte(v)) << ", toByte(srgbEncode) " << int(toByte(srgbEncode(v)));
    };
    const uint32_t one = 0x3f800000u;
    for (uint32_t bits = 0; bits <= one; bits += 61) {
        float v;
        std::memcpy(&v, &bits, sizeof v);
        check(v);
    }
    int steps = 0;
    float prev = 0.f;
    for (int k = 1; k <= 255; ++k) {
        // The least v of byte k, by the function itself (bisection on the bit patterns).
        uint32_t lo = 0, hi = one;
        while (lo < hi) {
            const uint32_t mid = lo + (hi - lo) / 2;
            float v;
            std::memcpy(&v, &mid, sizeof v);
            if (toByte(srgbEncode(v)) >= k) hi = mid;
            else lo = mid + 1;
        }
        float step;
        std::memcpy(&step, &lo, sizeof step);
        EXPECT_GT(step, prev);
        prev = step;
        float v = step;
        for (int i = 0; i < 4; ++i) v = std::nextafter(v, 0.f);
        for (int i = 0; i < 8; ++i, v = std::nextafter(v, 2.f)) check(v);
        steps += srgbByte(step) == k && srgbByte(std::nextafter(step, 0.f)) == k - 1;
    }
    EXPECT_EQ(steps, 255);
    for (float v : {-0.f, -1e-30f, -300.f, 1.f, 1.0000001f, 1.5f, 1e30f})
        check(v);
    EXPECT_EQ(srgbByte(std::nanf("")), 0);
    EXPECT_EQ(srgbByte(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(srgbByte(-std::numeric_limits<float>::infinity()), 0);
    EXPECT_EQ(srgbByte(0.5f), 188);
    EXPECT_EQ(mismatches, 0);
}

TEST(Image, ToByteHandlesOutOfRangeAndNonFinite) {
    EXPECT_EQ(toByte(-300.f), 0);
    EXPECT_EQ(toByte(-0.f), 0);
    EXPECT_EQ(toByte(std::nanf("")), 0);
    EXPECT_EQ(toByte(1.5f), 255);
    EXPECT_EQ(toByte(std::numeric_limits<float>::infinity()), 255);
    EXPECT_EQ(toByte(-std::numeric_limits<float>::infinity()), 0);
    EXPECT_EQ(toByte(0.5f), 128);  // rounds, 127.5 + 0.5
    EXPECT_EQ(toByte(1.f / 255.f), 1);
}

TEST(Image, ToneMapReinhardAndClamp) {
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_FLOAT_EQ(toneMap(1.f, ToneMap::Reinhard), 0.5f);
    EXPECT_FLOAT_EQ(toneMap(3.f, ToneMap::Reinhard), 0.75f);
    EXPECT_EQ(toneMap(inf, ToneMap::Reinhard), 1.f);
    EXPECT_EQ(toneMap(std::nanf(""), ToneMap::Reinhard), 0.f);
    EXPECT_EQ(toneMap(-2.f, ToneMap::Reinhard), 0.f);
    EXPECT_EQ(toneMap(1e30f, ToneMap::Reinhard), 1.f);
    EXPECT_EQ(toneMap(inf, ToneMap::Clamp), 1.f);
    EXPECT_EQ(toneMap(std::nanf(""), ToneMap::Clamp), 0.f);
    EXPECT_EQ(toneMap(0.25f, ToneMap::Clamp), 0.25f);
    EXPECT_EQ(toneMap(7.f, ToneMap::Clamp), 1.f);
}

namespace {
/// Khronos PBR Neutral written out from its specification one channel at a time, as the
/// scalar code before the four-lane version computed it: the bytes must not move.
Color neutralByTheSpec(Color c) {
    const float start = 0.8f - 0.04f, desaturation = 0.15f;
    for (int k = 0; k < 3; ++k) c[k] = c[k] > 0.f ? std::min(c[k], 1e30f) : 0.f;
    const float x = std::min(c.r, std::min(c.g, c.b));
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    for (int k = 0; k < 3; ++k) c[k] -= offset;
    const float peak = std::max(c.r, std::max(c.g, c.b));
    if (peak < start) return c;
    const float d = 1.f - start;
    const float newPeak = 1.f - d * d / (peak + d - start);
    const float g = 1.f - 1.f / (desaturation * (peak - newPeak) + 1.f);
    for (int k = 0; k < 3; ++k) c[k] = c[k] * (newPeak / peak) * (1.f - g) + newPeak * g;
    return c;
}
}  // namespace

// encodeRgb8 maps four pixels at once. Each pixel's bytes must be what it gets alone (a row's
// tail of 1, 2 or 3 pixels, a single RGBA pixel, a tile edge), and what the per-channel
// definition (Clamp, Reinhard) or the specification's PBR Neutral gives.
TEST(Image, EncodeRgb8MatchesThePixelByPixelDefinition) {
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<float> rgb;
    uint32_t state = 12345u;
    auto next = [&] { return state = state * 1664525u + 1013904223u; };
    const float special[] = {0.f, -0.f, -1.f, std::nanf(""), inf, -inf, 1e-40f, 0.0031308f, 0.08f, 0.76f, 0.7599f, 1.f, 1e30f, 3e38f};
    for (float a : special)
        for (float b : {0.f, 0.5f, 0.07f, 2.f, inf}) rgb.insert(rgb.end(), {a, b, 0.3f}), rgb.insert(rgb.end(), {b, 0.3f, a});
    for (int i = 0; i < 3000; ++i) {
        const float magnitude = std::ldexp(1.f, int(next() % 24) - 16);  // 2^-16 to 2^7
        rgb.push_back(magnitude * float(next() >> 8) / float(1u << 24));
    }
    while (rgb.size() % 3 != 0 || (rgb.size() / 3) % 4 != 1) rgb.push_back(0.25f);  // a tail of one pixel
    for (ToneMap op : {ToneMap::Clamp, ToneMap::Reinhard, ToneMap::PbrNeutral}) {
        for (float scale : {1.f, 0.37f, 8.f}) {
          for (size_t cut = 0; cut < 4; ++cut) {  // rows whose tails hold 1, 0, 3 and 2 pixels
            const size_t pixels = rgb.size() / 3 - cut;
            std::vector<uint8_t> all(3 * pixels);
            encodeRgb8(rgb.data(), 3 * pixels, op, all.data(), scale);
            int mismatches = 0;
            for (size_t p = 0; p < pixels; ++p) {
                uint8_t alone[3], rgba[4];
                encodeRgb8(&rgb[3 * p], 3, op, alone, scale);
                toRgba8Pixel(&rgb[3 * p], 1.f, op, rgba, scale);
                const Color c = neutralByTheSpec(scale * Color(rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]));
                for (int k = 0; k < 3; ++k) {
                    const float v = rgb[3 * p + k] * scale;
                    const uint8_t want = op == ToneMap::PbrNeutral ? toByte(srgbEncode(c[k])) : toByte(srgbEncode(toneMap(v, op)));
                    if ((all[3 * p + k] != want || alone[k] != want || rgba[k] != want) && ++mismatches <= 5)
                        ADD_FAILURE() << "tone map " << int(op) << ", scale " << scale << ", pixel " << p << " channel " << k << " (" << v
                                      << "): in a row " << int(all[3 * p + k]) << ", alone " << int(alone[k]) << ", RGBA "
                                      << int(rgba[k]) << ", defined " << int(want);
                }
            }
            EXPECT_EQ(mismatches, 0);
          }
        }
    }
}

TEST(Image, PngRoundTripAndNonFinitePixels) {
    Image img(3, 2);
    const float vals[] = {0.f, 0.18f, 0.5f, 1.f, 2.f, std::nanf(""), -1.f, std::numeric_limits<float>::infinity(), 0.0031308f};
    for (int i = 0; i < 18; ++i) img.data()[i] = vals[i % 9];
    const std::vector<uint8_t> rgb = toRgb8(img, ToneMap::Clamp);
    EXPECT_EQ(rgb[1], 118);
    EXPECT_EQ(rgb[5], 0);    // NaN
    EXPECT_EQ(rgb[7], 255);  // +inf
    const std::string dir = RAYFARM_TEST_OUT;
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/image_roundtrip.png";
    writePng(path, 3, 2, rgb);
    int w = 0, h = 0;
    EXPECT_EQ(readImageRgb8(path, w, h), rgb);
    EXPECT_EQ(w, 3);
    EXPECT_EQ(h, 2);
    EXPECT_THROW(readImageRgb8(dir + "/does-not-exist.png", w, h), std::runtime_error);
}

// Issue 47 #5: over an exact background, a pixel the model misses is the background's own bytes
// (every sRGB byte a #RRGGBB can name comes back unchanged, whatever the exposure and tone map),
// a pixel it covers is what an opaque render encodes, and an edge lies between the two.
TEST(Image, OverAnExactBackgroundMissesAreItsBytesAndCoveredPixelsAreTheModels) {
    const float model[3] = {0.3f, 0.05f, 0.9f};
    for (ToneMap op : {ToneMap::Clamp, ToneMap::Reinhard, ToneMap::PbrNeutral}) {
        for (int v = 0; v < 256; ++v) {
            const float lin = srgbDecode(float(v) / 255.f);
            const Color bg(lin, srgbDecode(float(255 - v) / 255.f), lin);
            uint8_t out[3];
            toRgb8OverPixel(model, 0.f, op, bg, out, 0.37f);
            ASSERT_EQ(int(out[0]), v) << "tone map " << int(op);
            ASSERT_EQ(int(out[1]), 255 - v);
        }
        const Color bg(srgbDecode(0x33 / 255.f), srgbDecode(0x66 / 255.f), srgbDecode(0x99 / 255.f));
        uint8_t covered[3], opaque[3], edge[3];
        toRgb8OverPixel(model, 1.f, op, bg, covered, 2.f);
        encodeRgb8(model, 3, op, opaque, 2.f);
        EXPECT_EQ(std::memcmp(covered, opaque, 3), 0);
        const float half[3] = {model[0] * 0.5f, model[1] * 0.5f, model[2] * 0.5f};  // premultiplied
        toRgb8OverPixel(half, 0.5f, op, bg, edge, 2.f);
        const uint8_t back[3] = {0x33, 0x66, 0x99};
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(int(edge[k]), std::min(int(opaque[k]), int(back[k])) + (opaque[k] != back[k] ? 1 : 0)) << k;
            EXPECT_LE(int(edge[k]), std::max(int(opaque[k]), int(back[k])) - (opaque[k] != back[k] ? 1 : 0)) << k;
        }
    }
}

// renderFrame's image over an exact background carries the backdrop; toRgb8 lays it under.
TEST(Image, ToRgb8LaysAnImageOverItsBackdrop) {
    Image img(2, 1, true);
    img.alphaData()[0] = 0.f;  // a miss: no colour
    img.alphaData()[1] = 1.f;
    img.pixel(1, 0)[0] = 0.5f;
    img.setBackdrop(Color(1.f, srgbDecode(0x80 / 255.f), 0.f));
    const std::vector<uint8_t> px = toRgb8(img, ToneMap::PbrNeutral, 4.f);
    EXPECT_EQ(std::vector<int>(px.begin(), px.begin() + 3), (std::vector<int>{255, 0x80, 0}));
    uint8_t opaque[3];
    encodeRgb8(img.pixel(1, 0), 3, ToneMap::PbrNeutral, opaque, 4.f);
    EXPECT_EQ(std::vector<int>(px.begin() + 3, px.end()), (std::vector<int>(opaque, opaque + 3)));
}
