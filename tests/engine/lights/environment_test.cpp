// Environment images: Blender's orientation, the rotation knob, real DWAB and RGBE files, bad
// files refused with a message naming them, and the prefiltered lighting of a uniform sky.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "engine/scene/env_lighting.h"
#include "engine/lights/environment.h"
#include "engine/util/errors.h"

using namespace rf;

namespace {

std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

const std::string kStudio = std::string(RAYFARM_SOURCE_DIR) + "/scenes/environments/studio.exr";

/// Black, with a one-texel-wide bright column at u = 0.5 (the image centre).
EquirectImage stripeAtCentre(int w = 64) {
    EquirectImage img;
    img.width = w;
    img.height = w / 2;
    img.texels.assign(size_t(img.width) * img.height, Color(0.f));
    for (int y = 0; y < img.height; ++y) {
        img.texels[size_t(y) * w + w / 2 - 1] = Color(1.f);
        img.texels[size_t(y) * w + w / 2] = Color(1.f);
    }
    return img;
}

/// A Radiance file with flat (not run-length encoded) RGBE pixels.
std::string rgbeFile(int w, int h, const std::vector<float>& rgb) {
    std::string out = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(h) + " +X " + std::to_string(w) + "\n";
    for (int i = 0; i < w * h; ++i) {
        const float m = std::max(rgb[3 * i], std::max(rgb[3 * i + 1], rgb[3 * i + 2]));
        int e = 0;
        const float f = std::frexp(m, &e) * 256.f / m;
        for (int k = 0; k < 3; ++k) out += char(static_cast<unsigned char>(rgb[3 * i + k] * f));
        out += char(static_cast<unsigned char>(e + 128));
    }
    return out;
}

void expectRefused(const std::string& bytes, const std::string& what) {
    try {
        decodeEnvironment(bytes, "bad.env");
        ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
        EXPECT_EQ(e.file(), "bad.env") << what;
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << what;
    }
}

}  // namespace

TEST(Environment, DirectionsMapAsBlenderDoes) {
    EXPECT_NEAR(equirectUv(Vec3(1, 0, 0)).x, 0.5f, 1e-6f);   // +X: the image centre
    EXPECT_NEAR(equirectUv(Vec3(1, 0, 0)).y, 0.5f, 1e-6f);
    EXPECT_NEAR(equirectUv(Vec3(0, 0, 1)).x, 0.75f, 1e-6f);  // +Z: three quarters across
    EXPECT_NEAR(equirectUv(Vec3(0, 1, 0)).y, 0.f, 1e-6f);    // +Y: the top row
    for (Vec2 uv : {Vec2(0.1f, 0.3f), Vec2(0.6f, 0.8f), Vec2(0.9f, 0.5f)}) {
        const Vec2 back = equirectUv(equirectDirection(uv));
        EXPECT_NEAR(back.x, uv.x, 1e-5f);
        EXPECT_NEAR(back.y, uv.y, 1e-5f);
    }
}

// equirectUv's polynomial atan2 against libm's double atan2 on a sphere of directions (all
// octants, the poles and the seam): within 4e-7 of a turn in u and of a half turn in v, a
// thousandth of a texel of an 8k map.
TEST(Environment, DirectionsMapAsLibmDoesToAThousandthOfATexel) {
    float worst = 0.f;
    Vec2 worstAt(0.f);
    for (int i = 0; i <= 400; ++i)
        for (int j = 0; j < 800; ++j) {
            const float theta = kPi * float(i) / 400.f, phi = 2.f * kPi * float(j) / 800.f;
            const Vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            const Vec2 uv = equirectUv(d);
            const float u = 0.5f + float(std::atan2(double(d.z), double(d.x)) / (2 * M_PI));
            // The polar angle of d as stored, in double (acos of the rounded d.y is itself off by
            // 2e-6 near the poles, where it is ill-conditioned).
            const float v = float(std::atan2(std::hypot(double(d.x), double(d.z)), double(d.y)) / M_PI);
            const float e = std::max(std::abs(uv.x - u), std::abs(uv.y - v));
            if (e > worst) worst = e, worstAt = Vec2(theta, phi);
        }
    EXPECT_LT(worst, 4e-7f) << "at theta " << worstAt.x << ", phi " << worstAt.y;
    EXPECT_EQ(equirectUv(Vec3(0.f)).x, 0.5f);           // atan2(0, 0) = 0, as libm's
    EXPECT_EQ(equirectUv(Vec3(-1, 0, -0.f)).x, 0.f);    // the seam, from below
    EXPECT_EQ(equirectUv(Vec3(-1, 0, 0.f)).x, 1.f);     // and from above, as libm's atan2
    EXPECT_EQ(equirectUv(Vec3(0, -1, 0)).y, 1.f);       // −Y: the bottom row
    // Denormal components keep their angle (0.5 turn + atan2(1, 2)/2π), and NaN stays NaN so
    // that sample() falls back to its first texel.
    EXPECT_NEAR(equirectUv(Vec3(2e-40f, 0.f, 1e-40f)).x, 0.5f + std::atan2(1.0, 2.0) / (2 * M_PI), 1e-6);
    EXPECT_TRUE(std::isnan(equirectUv(Vec3(1.f, 0.f, std::nanf(""))).x));
}

// The background of a packet's misses is looked up four directions at a time; each lane must
// be what the one-at-a-time look-up gives, bit for bit: the same directions as above plus the
// seam, the poles, signed zeros, denormals, and a lane with a NaN beside three good ones.
TEST(Environment, FourLaneLookUpsAreTheScalarOnesBitForBit) {
    const EnvironmentLight env(builtinStudioEnvironment(64), 37.f, 1.5f, 1);
    std::vector<Vec3> dirs;
    for (int i = 0; i <= 100; ++i)
        for (int j = 0; j < 200; ++j) {
            const float theta = kPi * float(i) / 100.f, phi = 2.f * kPi * float(j) / 200.f;
            dirs.emplace_back(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
        }
    for (const Vec3& d : {Vec3(-1, 0, -0.f), Vec3(-1, 0, 0.f), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(-0.f, -1, -0.f),
                          Vec3(2e-40f, 0.f, 1e-40f), Vec3(-2e-40f, 1.f, -1e-40f), Vec3(0.f), Vec3(1.f, 0.f, std::nanf("")),
                          Vec3(0.6f, 0.f, 0.8f), Vec3(-0.6f, 0.f, 0.8f)})
        dirs.push_back(d);
    while (dirs.size() % 4) dirs.emplace_back(0.f, 0.f, 1.f);
    size_t differ = 0;
    for (size_t k = 0; k < dirs.size(); k += 4) {
        Color four[4];
        env.radiance4(&dirs[k], four);
        for (int i = 0; i < 4; ++i) {
            const Color one = env.radiance(dirs[k + i]);
            differ += std::memcmp(&one, &four[i], sizeof one) != 0;
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << dirs.size();
    // And equirectUv4 itself, where no lane holds a NaN.
    for (size_t k = 0; k + 4 <= dirs.size(); k += 4) {
        const F4 d[3] = {{dirs[k].x, dirs[k + 1].x, dirs[k + 2].x, dirs[k + 3].x},
                         {dirs[k].y, dirs[k + 1].y, dirs[k + 2].y, dirs[k + 3].y},
                         {dirs[k].z, dirs[k + 1].z, dirs[k + 2].z, dirs[k + 3].z}};
        F4 u, v;
        bool nan = false;
        for (int i = 0; i < 4; ++i) nan |= std::isnan(dirs[k + i].x) || std::isnan(dirs[k + i].y) || std::isnan(dirs[k + i].z);
        ASSERT_EQ(equirectUv4(d, u, v), !nan);
        if (nan) continue;
        for (int i = 0; i < 4; ++i) {
            const Vec2 one = equirectUv(dirs[k + i]);
            const float ui = u[i], vi = v[i];  // a lane by value: clang takes no vector element's address
            EXPECT_EQ(std::memcmp(&one.x, &ui, 4), 0) << k + i;
            EXPECT_EQ(std::memcmp(&one.y, &vi, 4), 0) << k + i;
        }
    }
}

TEST(Environment, StripeAtTheCentreIsSeenLookingAlongPlusX) {
    const EnvironmentLight env(stripeAtCentre(), 0.f, 1.f, 1);
    EXPECT_GT(env.radiance(Vec3(1, 0, 0)).g, 0.9f);
    EXPECT_LT(env.radiance(Vec3(-1, 0, 0)).g, 1e-6f);
    EXPECT_LT(env.radiance(Vec3(0, 0, 1)).g, 1e-6f);
    EXPECT_LT(env.radiance(Vec3(0, 0, -1)).g, 1e-6f);
}

TEST(Environment, RotationTurnsAboutPlusY) {
    // +90°: what +X saw is now seen towards −Z (right-handed about +Y).
    const EnvironmentLight env(stripeAtCentre(), 90.f, 2.f, 1);
    EXPECT_GT(env.radiance(Vec3(0, 0, -1)).g, 1.8f);  // intensity 2
    EXPECT_LT(env.radiance(Vec3(1, 0, 0)).g, 1e-6f);
}

TEST(Environment, OctahedralMapRoundTripsEveryDirection) {
    // Axes, the poles, the fold edges (|x| + |z| = 1 below the equator) and a spread of others.
    std::vector<Vec3> dirs = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1),
                              Vec3(1, -1e-6f, 0), Vec3(0.5f, -0.5f, 0.5f), Vec3(-0.3f, -0.9f, 0.1f)};
    for (int i = 0; i < 2000; ++i) {
        const float z = 1.f - 2.f * (i + 0.5f) / 2000.f, phi = 2.39996323f * i;  // a Fibonacci spiral
        const float s = std::sqrt(1.f - z * z);
        dirs.emplace_back(s * std::cos(phi), z, s * std::sin(phi));
    }
    for (const Vec3& raw : dirs) {
        const Vec3 d = glm::normalize(raw);
        const Vec2 uv = octahedralUv(d);
        ASSERT_GE(uv.x, 0.f);
        ASSERT_LE(uv.x, 1.f);
        ASSERT_GE(uv.y, 0.f);
        ASSERT_LE(uv.y, 1.f);
        const Vec3 back = octahedralDirection(uv);
        EXPECT_LT(glm::length(back - d), 1e-5f) << d.x << " " << d.y << " " << d.z;
        // Length does not matter, only direction.
        EXPECT_LT(glm::length(octahedralUv(7.f * d) - uv), 1e-6f);
    }
}

TEST(Environment, OctahedralLookUpsAreSeamlessAcrossTheFolds) {
    // A smooth function of direction, stored at 16² texels: bilinear look-ups anywhere, including
    // beside the edges and corners where the border copies texels from across a fold, stay within
    // the interpolation error of a texel. That error is largest across the map's creases (the
    // axes and the equator, where the direction bends): 0.073 here, halving with each doubling of
    // the size. A border left at a constant is off by 0.73 beside the edges.
    auto f = [](const Vec3& d) { return Color(2.f + d.x, 2.f + d.y, 2.f + d.z); };
    const OctahedralImage img = OctahedralImage::build(16, 1, f);
    ASSERT_EQ(img.texels.size(), 18u * 18u);
    float worst = 0.f;
    for (int i = 0; i < 20000; ++i) {
        const float z = 1.f - 2.f * (i + 0.5f) / 20000.f, phi = 2.39996323f * i;
        const float s = std::sqrt(1.f - z * z);
        const Vec3 d(s * std::cos(phi), z, s * std::sin(phi));
        const Color got = img.sample(d), want = f(d);
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(got[k] - want[k]));
    }
    EXPECT_LT(worst, 0.1f);
    // Non-finite directions give a finite texel, not a read outside the map.
    const Color nan = img.sample(Vec3(std::nanf(""), 0.f, 0.f));
    EXPECT_TRUE(std::isfinite(nan.r) && std::isfinite(nan.g) && std::isfinite(nan.b));
}

TEST(Environment, UniformSkyLightsEveryNormalAndRoughnessAlike) {
    EquirectImage sky;
    sky.width = 128;
    sky.height = 64;
    sky.texels.assign(size_t(sky.width) * sky.height, Color(0.5f));
    const EnvironmentLight env(sky, 0.f, 1.f, 1);
    for (const Vec3& n : {Vec3(0, 1, 0), Vec3(1, 0, 0), glm::normalize(Vec3(-1, -2, 3))}) {
        // Irradiance/π of a uniform radiance L is L; the equirect's texel sum gets within 1%.
        EXPECT_NEAR(env.diffuse(n).r, 0.5f, 0.005f);
        for (float r : {0.f, 0.3f, 0.7f, 1.f}) EXPECT_NEAR(env.specular(n, r).r, 0.5f, 1e-3f) << r;
    }
}

TEST(Environment, StudioExrWithDwabCompressionLoads) {
    const std::string bytes = readFile(kStudio);
    ASSERT_GT(bytes.size(), 1000u);
    const EquirectImage img = decodeEnvironment(bytes, kStudio);
    EXPECT_EQ(img.width, 1024);
    EXPECT_EQ(img.height, 512);
    double sum = 0.0;
    float peak = 0.f;
    for (const Color& c : img.texels) {
        sum += c.g;
        peak = std::max(peak, c.g);
    }
    // A studio: a dim room (mean radiance well below 1) with lights far brighter than it.
    const double mean = sum / img.texels.size();
    EXPECT_GT(mean, 0.01);
    EXPECT_LT(mean, 5.0);
    EXPECT_GT(peak, 10.0 * mean);
}

TEST(Environment, RadianceHdrRoundTrips) {
    const int w = 32, h = 16;
    std::vector<float> px(size_t(w) * h * 3);
    for (int i = 0; i < w * h; ++i) {
        px[3 * i] = 0.003f * i;  // below g, which sets the shared exponent
        px[3 * i + 1] = 2.f;
        px[3 * i + 2] = 0.25f;
    }
    const std::string whole = rgbeFile(w, h, px);
    const EquirectImage img = decodeEnvironment(whole, "roundtrip.hdr");
    ASSERT_EQ(img.width, w);
    ASSERT_EQ(img.height, h);
    for (int i = 0; i < w * h; i += 37) {
        // RGBE shares one exponent, set by the largest channel (g = 2 here): every channel is
        // stored in steps of 2^(e−8) = 1/64, truncated.
        EXPECT_NEAR(img.texels[size_t(i)].r, px[3 * i], 1.f / 64.f);
        EXPECT_NEAR(img.texels[size_t(i)].g, 2.f, 1.f / 64.f);
    }
    // Truncated: RGBE data cut in half is refused, not filled with black.
    expectRefused(whole.substr(0, whole.size() / 2), "truncated .hdr");
}

TEST(Environment, BadFilesAreRefusedNamingTheFile) {
    const std::string exr = readFile(kStudio);
    expectRefused(exr.substr(0, exr.size() / 2), "truncated .exr");
    std::string corrupt = exr;
    for (size_t i = exr.size() / 3; i < exr.size() / 3 + 2000; ++i) corrupt[i] = char(i * 131);
    expectRefused(corrupt, "corrupt .exr");
    expectRefused(exr.substr(0, 4), "EXR magic only");
    expectRefused("", "empty file");
    expectRefused("P6\n2 2\n255\n............", "a PPM");
    expectRefused("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 200000\n", "huge .hdr");
    expectRefused("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 0\n", "empty .hdr");
}

TEST(Environment, BuiltinStudioIsLitFromAboveAndFinite) {
    const EquirectImage img = builtinStudioEnvironment(128);
    ASSERT_EQ(img.width, 128);
    ASSERT_EQ(img.height, 64);
    for (const Color& c : img.texels) ASSERT_TRUE(isFinite(c) && c.r >= 0.f);
    const EnvironmentLight env(img, 0.f, 1.f, 1);
    EXPECT_GT(env.diffuse(Vec3(0, 1, 0)).g, 2.f * env.diffuse(Vec3(0, -1, 0)).g);
}

// Issue 30 #4: an 8 x 4,194,304 image filtered in 70 s against 1.7 s for the same pixel count
// at 2:1. The mip chain stopped halving once the short side was 8 wide, so the irradiance summed
// every texel of the full image for each of its 576. Now the chain goes on until the level is
// small in pixels, whatever the shape: the work below is what the time follows (bench/
// bench_environment.sh times it).
TEST(Environment, FilteringWorkFollowsThePixelCountWhateverTheShape) {
    // About 2^17 pixels each: 2:1, 1:1, 8:1 and 1:8 (what a file may have), then strips no file
    // may have (refused from the header below) but the filtering must not be slow on either.
    struct Shape {
        int w, h;
        bool accepted;
    };
    for (const Shape& s : {Shape{512, 256, true}, Shape{362, 362, true}, Shape{1024, 128, true}, Shape{128, 1024, true},
                           Shape{8, 16384, false}, Shape{16384, 8, false}, Shape{1, 1 << 17, false}}) {
        EquirectImage img;
        img.width = s.w;
        img.height = s.h;
        img.texels.assign(size_t(s.w) * s.h, Color(0.25f));
        const size_t pixels = img.texels.size();
        const EnvironmentLight env(std::move(img), 0.f, 1.f, 2);
        const std::string shape = std::to_string(s.w) + "x" + std::to_string(s.h);
        // The 2:1 image sums 128x64 texels for each irradiance texel; no shape sums more than
        // 65,536 (the 8-wide strip summed all 131,072).
        EXPECT_LE(env.irradianceSourcePixels(), 65536u) << shape;
        // Each level at least halves the one before (a strip halves only its long side): the
        // levels together hold at most as many pixels as the image, a third of it at 2:1.
        EXPECT_LE(env.mipPixels(), pixels) << shape;
        for (const Vec3& n : {Vec3(0, 1, 0), Vec3(1, 0, 0), glm::normalize(Vec3(-1, -2, 3))}) {
            if (!s.accepted) {  // a strip has too few columns to integrate over azimuth: finite is all
                EXPECT_TRUE(isFinite(env.diffuse(n))) << shape;
                continue;
            }
            // Still right: a uniform sky lights every normal and roughness alike.
            EXPECT_NEAR(env.diffuse(n).r, 0.25f, 0.0025f) << shape;
            for (float r : {0.3f, 1.f}) EXPECT_NEAR(env.specular(n, r).r, 0.25f, 1e-3f) << shape << " roughness " << r;
        }
    }
}

// The shape comes from the header, before any pixel is decoded: an equirect is 2:1, and past
// 8:1 either way the file is refused in one line naming it and its size.
TEST(Environment, HeaderWithAbsurdProportionsIsRefused) {
    const auto header = [](int w, int h) {
        return "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(h) + " +X " + std::to_string(w) + "\n";
    };
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{8, 4194304}, {9, 1}, {1, 9}, {65536, 8}}) {
        try {
            decodeEnvironment(header(w, h), "strip.hdr");
            ADD_FAILURE() << w << "x" << h << " accepted";
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()), "strip.hdr: environment image of " + std::to_string(w) + "x" + std::to_string(h) +
                                                 " is not an equirectangular panorama (expected about 2:1; refused past 8:1 either way)");
        }
    }
    // 8:1 and 1:8 are still taken (with their pixels).
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{64, 8}, {8, 64}}) {
        const EquirectImage img = decodeEnvironment(rgbeFile(w, h, std::vector<float>(size_t(w) * h * 3, 1.f)), "ok.hdr");
        EXPECT_EQ(img.width, w);
        EXPECT_EQ(img.height, h);
    }
}
