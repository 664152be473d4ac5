#include "engine/util/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rf {

namespace {

void checkSizes(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height) {
    if (width <= 0 || height <= 0) throw std::invalid_argument("image metrics: empty image");
    const size_t n = size_t(width) * size_t(height) * 3;
    if (a.size() != n || b.size() != n)
        throw std::invalid_argument("image metrics: expected " + std::to_string(n) + " bytes per image, got " +
                                    std::to_string(a.size()) + " and " + std::to_string(b.size()));
}

std::vector<double> luma(const std::vector<uint8_t>& rgb, size_t pixels) {
    std::vector<double> y(pixels);
    for (size_t i = 0; i < pixels; ++i)
        y[i] = (0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2]) / 255.0;
    return y;
}

/// Normalised 1D Gaussian of `size` taps; the 2D window is its outer product (separable).
std::vector<double> gaussianTaps(int size, double sigma) {
    std::vector<double> g(size);
    const double c = 0.5 * (size - 1);
    double sum = 0.0;
    for (int i = 0; i < size; ++i) {
        const double x = i - c;
        g[i] = std::exp(-x * x / (2.0 * sigma * sigma));
        sum += g[i];
    }
    for (double& v : g) v /= sum;
    return g;
}

/// "Valid" separable filtering: output is (w − k + 1) × (h − k + 1).
std::vector<double> filterValid(const std::vector<double>& src, int w, int h, const std::vector<double>& taps) {
    const int k = static_cast<int>(taps.size());
    const int ow = w - k + 1, oh = h - k + 1;
    std::vector<double> rows(size_t(ow) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < ow; ++x) {
            double s = 0.0;
            for (int i = 0; i < k; ++i) s += taps[i] * src[size_t(y) * w + x + i];
            rows[size_t(y) * ow + x] = s;
        }
    std::vector<double> out(size_t(ow) * oh);
    for (int y = 0; y < oh; ++y)
        for (int x = 0; x < ow; ++x) {
            double s = 0.0;
            for (int i = 0; i < k; ++i) s += taps[i] * rows[size_t(y + i) * ow + x];
            out[size_t(y) * ow + x] = s;
        }
    return out;
}

}  // namespace

double rmseRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height) {
    checkSizes(a, b, width, height);
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        const double d = (double(a[i]) - double(b[i])) / 255.0;
        sum += d * d;
    }
    return std::sqrt(sum / double(a.size()));
}

double psnrFromRmse(double rmse) {
    if (rmse <= 0.0) return std::numeric_limits<double>::infinity();
    return -20.0 * std::log10(rmse);
}

double maxAbsErrorRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height) {
    checkSizes(a, b, width, height);
    int m = 0;
    for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(int(a[i]) - int(b[i])));
    return m / 255.0;
}

double errorQuantileRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height,
                         double q) {
    checkSizes(a, b, width, height);
    // Counting sort over the 256 possible differences: exact and linear in the pixel count.
    size_t count[256] = {0};
    const size_t n = size_t(width) * height;
    for (size_t i = 0; i < n; ++i) {
        int m = 0;
        for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a[3 * i + c]) - int(b[3 * i + c])));
        ++count[m];
    }
    const double qc = std::clamp(q, 0.0, 1.0);
    const size_t rank = std::max<size_t>(1, static_cast<size_t>(std::ceil(qc * double(n))));
    size_t seen = 0;
    for (int v = 0; v < 256; ++v) {
        seen += count[v];
        if (seen >= rank) return v / 255.0;
    }
    return 1.0;
}

namespace {

/// The SSIM of every window that fits inside the image ("valid"), row by row: (w − k + 1) ×
/// (h − k + 1) values for the window side k; the window at (x, y) is centred on pixel
/// (x + k/2, y + k/2).
std::vector<double> ssimMap(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height, int& k) {
    const size_t n = size_t(width) * height;
    const std::vector<double> x = luma(a, n), y = luma(b, n);
    std::vector<double> xx(n), yy(n), xy(n);
    for (size_t i = 0; i < n; ++i) {
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    k = std::min({11, width, height});
    const std::vector<double> taps = gaussianTaps(k, 1.5);
    const std::vector<double> mx = filterValid(x, width, height, taps), my = filterValid(y, width, height, taps);
    const std::vector<double> sxx = filterValid(xx, width, height, taps), syy = filterValid(yy, width, height, taps);
    const std::vector<double> sxy = filterValid(xy, width, height, taps);
    const double c1 = (0.01 * 1.0) * (0.01 * 1.0), c2 = (0.03 * 1.0) * (0.03 * 1.0);
    std::vector<double> out(mx.size());
    for (size_t i = 0; i < mx.size(); ++i) {
        const double vx = sxx[i] - mx[i] * mx[i], vy = syy[i] - my[i] * my[i], cxy = sxy[i] - mx[i] * my[i];
        out[i] = ((2.0 * mx[i] * my[i] + c1) * (2.0 * cxy + c2)) / ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
    }
    return out;
}

}  // namespace

double ssimRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height) {
    checkSizes(a, b, width, height);
    int k = 0;
    const std::vector<double> map = ssimMap(a, b, width, height, k);
    double sum = 0.0;
    for (double v : map) sum += v;
    return sum / double(map.size());
}

double ssimRgb8Masked(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height,
                      const std::vector<uint8_t>& mask) {
    checkSizes(a, b, width, height);
    if (mask.size() != size_t(width) * height) throw std::invalid_argument("ssimRgb8Masked: mask size does not match");
    int k = 0;
    const std::vector<double> map = ssimMap(a, b, width, height, k);
    const int mw = width - k + 1, mh = height - k + 1;
    double sum = 0.0;
    size_t used = 0;
    for (int y = 0; y < mh; ++y)
        for (int x = 0; x < mw; ++x)
            if (mask[size_t(y + k / 2) * width + size_t(x + k / 2)]) {
                sum += map[size_t(y) * mw + x];
                ++used;
            }
    return used ? sum / double(used) : std::nan("");
}

ImageErrorMetrics compareRgb8(const std::vector<uint8_t>& test, const std::vector<uint8_t>& reference, int width,
                              int height) {
    ImageErrorMetrics m;
    m.rmse = rmseRgb8(test, reference, width, height);
    m.psnr = psnrFromRmse(m.rmse);
    m.maxError = maxAbsErrorRgb8(test, reference, width, height);
    m.ssim = ssimRgb8(test, reference, width, height);
    return m;
}

void errorColor(double error, double scale, uint8_t rgb[3]) {
    // Piecewise-linear ramp through five stops; NaN and non-positive scales show as full error.
    static const double kStops[6][3] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    double u = scale > 0.0 ? error / scale : 1.0;
    if (!(u >= 0.0)) u = std::isnan(u) ? 1.0 : 0.0;
    u = std::min(u, 1.0) * 5.0;
    const int i = std::min(static_cast<int>(u), 4);
    const double f = u - i;
    for (int c = 0; c < 3; ++c) {
        const double v = kStops[i][c] + f * (kStops[i + 1][c] - kStops[i][c]);
        rgb[c] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
    }
}

std::vector<uint8_t> falseColorErrorRgb8(const std::vector<uint8_t>& test, const std::vector<uint8_t>& reference,
                                         int width, int height, double scale) {
    checkSizes(test, reference, width, height);
    const size_t n = size_t(width) * height;
    std::vector<uint8_t> out(n * 3);
    for (size_t i = 0; i < n; ++i) {
        int m = 0;
        for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(test[3 * i + c]) - int(reference[3 * i + c])));
        errorColor(m / 255.0, scale, &out[3 * i]);
    }
    return out;
}

}  // namespace rf
