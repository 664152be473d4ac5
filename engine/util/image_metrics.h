#pragma once
/// Error of an image against a reference: RMSE, PSNR, largest per-pixel error, SSIM, and a
/// false-colour picture of where the error is.
///
/// All metrics work on what a viewer sees: 8-bit RGB after tone mapping and sRGB encoding, with
/// values scaled to [0, 1] (so PSNR has a well-defined peak of 1; linear HDR radiance has none).
#include <cstdint>
#include <vector>

namespace rf {

/// Error of one image against a reference, all on the [0, 1] scale of 8-bit sRGB.
struct ImageErrorMetrics {
    double rmse = 0.0;      ///< root mean square over every channel of every pixel
    double psnr = 0.0;      ///< 20·log10(1 / rmse) dB; +infinity for identical images
    double maxError = 0.0;  ///< largest absolute channel difference of any pixel
    double ssim = 1.0;      ///< mean SSIM on luma, Gaussian 11×11 window (σ = 1.5)
};

/// Root mean square difference of two 8-bit RGB images of width × height pixels, in [0, 1].
double rmseRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height);

/// 20·log10(1 / rmse) with a peak of 1; +infinity when rmse is 0.
double psnrFromRmse(double rmse);

/// Largest |a − b| over all channels and pixels, in [0, 1].
double maxAbsErrorRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height);

/// The q-quantile (0..1, nearest rank) of the per-pixel largest channel difference, in [0, 1]:
/// a scale for the false-colour image that a handful of extreme pixels cannot wash out.
double errorQuantileRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height,
                         double q);

/// Mean structural similarity (Wang, Bovik, Sheikh, Simoncelli 2004) of the luma planes
/// (Y = 0.299 R + 0.587 G + 0.114 B on the sRGB-encoded values, as MATLAB's rgb2gray), with the
/// paper's circular Gaussian window of 11×11 and σ = 1.5, K1 = 0.01, K2 = 0.03, L = 1, over the
/// windows that fit inside the image ("valid"). Images smaller than 11 pixels on a side use a
/// window as large as the smaller side.
double ssimRgb8(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height);

/// ssimRgb8's windows averaged over those centred on a pixel where mask (one byte a pixel) is
/// non-zero: SSIM on the pixels a model covers, not on a background that would hide it. NaN when
/// no window qualifies.
double ssimRgb8Masked(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height,
                      const std::vector<uint8_t>& mask);

/// Every metric above at once. Throws std::invalid_argument if the sizes do not match.
ImageErrorMetrics compareRgb8(const std::vector<uint8_t>& test, const std::vector<uint8_t>& reference, int width,
                              int height);

/// Maps an error in [0, scale] to a colour: black (0) → blue → cyan → green → yellow → red
/// (≥ scale). Returns 8-bit RGB.
void errorColor(double error, double scale, uint8_t rgb[3]);

/// False-colour error image: per pixel the largest channel difference, coloured by errorColor.
std::vector<uint8_t> falseColorErrorRgb8(const std::vector<uint8_t>& test, const std::vector<uint8_t>& reference,
                                         int width, int height, double scale);

}  // namespace rf
