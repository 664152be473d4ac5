// Image error metrics against closed forms and a direct (non-separable) SSIM.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "engine/util/image_metrics.h"

namespace rf {
namespace {

std::vector<uint8_t> randomImage(int w, int h, int lo, int hi, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(lo, hi);
    std::vector<uint8_t> img(size_t(w) * h * 3);
    for (uint8_t& v : img) v = static_cast<uint8_t>(d(rng));
    return img;
}

/// SSIM straight from the paper's definition: a full 2D weighted window at every valid position.
double directSsim(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int w, int h) {
    const int k = 11;
    double g[k], sum = 0;
    for (int i = 0; i < k; ++i) sum += g[i] = std::exp(-(i - 5.0) * (i - 5.0) / (2 * 1.5 * 1.5));
    auto Y = [](const std::vector<uint8_t>& im, int x, int y, int w) {
        const uint8_t* p = &im[3 * (size_t(y) * w + x)];
        return (0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]) / 255.0;
    };
    double total = 0;
    int count = 0;
    for (int y0 = 0; y0 + k <= h; ++y0)
        for (int x0 = 0; x0 + k <= w; ++x0) {
            double mx = 0, my = 0;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    const double wt = g[i] * g[j] / (sum * sum);
                    mx += wt * Y(a, x0 + i, y0 + j, w);
                    my += wt * Y(b, x0 + i, y0 + j, w);
                }
            double vx = 0, vy = 0, cxy = 0;
            for (int j = 0; j < k; ++j)
                for (int i = 0; i < k; ++i) {
                    const double wt = g[i] * g[j] / (sum * sum);
                    const double dx = Y(a, x0 + i, y0 + j, w) - mx, dy = Y(b, x0 + i, y0 + j, w) - my;
                    vx += wt * dx * dx;
                    vy += wt * dy * dy;
                    cxy += wt * dx * dy;
                }
            const double c1 = 1e-4, c2 = 9e-4;
            total += (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
            ++count;
        }
    return total / count;
}

TEST(ImageMetrics, IdenticalImagesHaveZeroErrorInfinitePsnrAndSsimOne) {
    const auto a = randomImage(37, 23, 0, 255, 1);
    const ImageErrorMetrics m = compareRgb8(a, a, 37, 23);
    EXPECT_EQ(m.rmse, 0.0);
    EXPECT_TRUE(std::isinf(m.psnr) && m.psnr > 0);
    EXPECT_EQ(m.maxError, 0.0);
    EXPECT_NEAR(m.ssim, 1.0, 1e-12);
}

TEST(ImageMetrics, ConstantOffsetGivesKnownRmseAndPsnr) {
    // No clipping: values 0..200 plus 10 stay in range, so every channel differs by exactly 10.
    const auto a = randomImage(40, 30, 0, 200, 2);
    auto b = a;
    for (uint8_t& v : b) v = static_cast<uint8_t>(v + 10);
    const ImageErrorMetrics m = compareRgb8(b, a, 40, 30);
    EXPECT_NEAR(m.rmse, 10.0 / 255.0, 1e-12);
    EXPECT_NEAR(m.psnr, 20.0 * std::log10(255.0 / 10.0), 1e-9);  // 28.13 dB
    EXPECT_NEAR(m.maxError, 10.0 / 255.0, 1e-12);
}

TEST(ImageMetrics, RmseOfOnePixelDifferenceIsItsShareOfTheImage) {
    std::vector<uint8_t> a(4 * 4 * 3, 100), b = a;
    b[0] = 100 + 51;  // one channel of one pixel differs by 0.2
    EXPECT_NEAR(rmseRgb8(a, b, 4, 4), std::sqrt(0.2 * 0.2 / 48.0), 1e-12);
    EXPECT_NEAR(maxAbsErrorRgb8(a, b, 4, 4), 0.2, 1e-12);
}

TEST(ImageMetrics, PsnrFromRmseClosedForm) {
    EXPECT_DOUBLE_EQ(psnrFromRmse(1.0), 0.0);
    EXPECT_NEAR(psnrFromRmse(0.1), 20.0, 1e-12);
    EXPECT_NEAR(psnrFromRmse(0.01), 40.0, 1e-12);
    EXPECT_TRUE(std::isinf(psnrFromRmse(0.0)));
}

TEST(ImageMetrics, SsimOfFlatImagesIsTheLuminanceTerm) {
    // Flat grey images: σ = 0, so SSIM = (2ab + C1) / (a² + b² + C1).
    const std::vector<uint8_t> a(32 * 32 * 3, 50), b(32 * 32 * 3, 200);
    const double x = 50 / 255.0, y = 200 / 255.0, c1 = 1e-4;
    EXPECT_NEAR(ssimRgb8(a, b, 32, 32), (2 * x * y + c1) / (x * x + y * y + c1), 1e-9);
}

TEST(ImageMetrics, SsimMatchesTheDirectDefinition) {
    const auto a = randomImage(24, 19, 0, 255, 3);
    auto b = a;
    std::mt19937 rng(4);
    std::normal_distribution<double> noise(0.0, 20.0);
    for (uint8_t& v : b) v = static_cast<uint8_t>(std::clamp(v + noise(rng), 0.0, 255.0));
    const double direct = directSsim(a, b, 24, 19);
    EXPECT_NEAR(ssimRgb8(a, b, 24, 19), direct, 1e-9);
    EXPECT_LT(direct, 0.99);  // the noise must matter, or the comparison proves nothing
}

TEST(ImageMetrics, SsimFallsAsNoiseGrowsAndIsSymmetric) {
    const auto a = randomImage(48, 32, 40, 215, 5);
    double last = 1.0;
    for (double sigma : {2.0, 8.0, 32.0}) {
        auto b = a;
        std::mt19937 rng(6);
        std::normal_distribution<double> noise(0.0, sigma);
        for (uint8_t& v : b) v = static_cast<uint8_t>(std::clamp(std::round(v + noise(rng)), 0.0, 255.0));
        const double s = ssimRgb8(a, b, 48, 32);
        EXPECT_LT(s, last) << "sigma " << sigma;
        EXPECT_NEAR(s, ssimRgb8(b, a, 48, 32), 1e-12);
        last = s;
    }
}

TEST(ImageMetrics, SmallImagesUseASmallerWindow) {
    const auto a = randomImage(5, 3, 0, 255, 7);
    EXPECT_NEAR(ssimRgb8(a, a, 5, 3), 1.0, 1e-12);
}

TEST(ImageMetrics, MismatchedSizesThrow) {
    const std::vector<uint8_t> a(12, 0), b(15, 0);
    EXPECT_THROW(compareRgb8(a, b, 2, 2), std::invalid_argument);
    EXPECT_THROW(rmseRgb8(a, a, 0, 4), std::invalid_argument);
}

TEST(ImageMetrics, ErrorQuantileByNearestRank) {
    // Ten pixels whose largest channel differences are 0, 10, 20, ..., 90 levels.
    std::vector<uint8_t> a(10 * 3, 100), b = a;
    for (int p = 0; p < 10; ++p) b[3 * p + (p % 3)] = static_cast<uint8_t>(100 + 10 * p);
    EXPECT_NEAR(errorQuantileRgb8(a, b, 10, 1, 1.0), 90 / 255.0, 1e-12);
    EXPECT_NEAR(errorQuantileRgb8(a, b, 10, 1, 0.9), 80 / 255.0, 1e-12);  // rank 9 of 10
    EXPECT_NEAR(errorQuantileRgb8(a, b, 10, 1, 0.5), 40 / 255.0, 1e-12);  // rank 5
    EXPECT_NEAR(errorQuantileRgb8(a, b, 10, 1, 0.0), 0.0, 1e-12);         // rank 1
}

TEST(ImageMetrics, ErrorColorRampEndsAndMiddle) {
    uint8_t c[3];
    errorColor(0.0, 0.5, c);
    EXPECT_EQ(c[0], 0); EXPECT_EQ(c[1], 0); EXPECT_EQ(c[2], 0);
    errorColor(0.5, 0.5, c);
    EXPECT_EQ(c[0], 255); EXPECT_EQ(c[1], 0); EXPECT_EQ(c[2], 0);
    errorColor(7.0, 0.5, c);  // beyond the scale saturates
    EXPECT_EQ(c[0], 255); EXPECT_EQ(c[1], 0); EXPECT_EQ(c[2], 0);
    errorColor(0.25, 0.5, c);  // u = 2.5: half way from cyan to green
    EXPECT_EQ(c[0], 0); EXPECT_EQ(c[1], 255); EXPECT_EQ(c[2], 128);
    errorColor(std::nan(""), 0.5, c);
    EXPECT_EQ(c[0], 255); EXPECT_EQ(c[1], 0);
}

TEST(ImageMetrics, FalseColorMarksOnlyDifferingPixels) {
    std::vector<uint8_t> a(3 * 2 * 3, 80), b = a;
    b[3 * 4 + 1] = 80 + 51;  // pixel 4, green channel, error 0.2 = the scale
    const auto img = falseColorErrorRgb8(b, a, 3, 2, 0.2);
    for (int p = 0; p < 6; ++p) {
        const bool hot = p == 4;
        EXPECT_EQ(img[3 * p], hot ? 255 : 0) << p;
        EXPECT_EQ(img[3 * p + 1], 0) << p;
        EXPECT_EQ(img[3 * p + 2], 0) << p;
    }
}

TEST(ImageMetrics, MaskedSsimScoresOnlyTheMaskedWindows) {
    // 40×40: a gradient in the left half; the right half differs between the two images.
    const int w = 40, h = 40;
    std::vector<uint8_t> a(3 * w * h), b;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) a[3 * (y * w + x) + c] = uint8_t(4 * x + 2 * y);
    b = a;
    for (int y = 0; y < h; ++y)
        for (int x = 25; x < w; ++x) b[3 * (y * w + x)] = uint8_t((x * 37 + y * 91) % 256);
    std::vector<uint8_t> left(w * h, 0), right(w * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) (x < 15 ? left : right)[y * w + x] = x < 15 || x >= 30;
    // Windows centred left of x = 15 reach at most to x = 19: they see identical pixels.
    EXPECT_DOUBLE_EQ(ssimRgb8Masked(a, b, w, h, left), 1.0);
    EXPECT_LT(ssimRgb8Masked(a, b, w, h, right), 0.9);
    EXPECT_LT(ssimRgb8(a, b, w, h), 1.0);
    EXPECT_TRUE(std::isnan(ssimRgb8Masked(a, b, w, h, std::vector<uint8_t>(w * h, 0))));
    EXPECT_THROW(ssimRgb8Masked(a, b, w, h, std::vector<uint8_t>(3, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace rf
