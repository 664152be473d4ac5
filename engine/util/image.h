#pragma once
/// Linear float RGB framebuffer, tone mapping, sRGB encoding and PNG files.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/util/settings.h"
#include "engine/util/vec_math.h"

namespace rf {

class Image {
public:
    Image() = default;
    /// withAlpha: also a coverage plane (0 transparent … 1 opaque); the colour is then
    /// premultiplied by it.
    Image(int width, int height, bool withAlpha = false)
        : w_(width), h_(height), rgb_(size_t(width) * height * 3, 0.f), alpha_(withAlpha ? size_t(width) * height : 0, 1.f) {}

    int width() const { return w_; }
    int height() const { return h_; }
    float* data() { return rgb_.data(); }
    const float* data() const { return rgb_.data(); }
    float* pixel(int x, int y) { return &rgb_[3 * (size_t(y) * w_ + x)]; }
    const float* pixel(int x, int y) const { return &rgb_[3 * (size_t(y) * w_ + x)]; }
    bool hasAlpha() const { return !alpha_.empty(); }
    /// Coverage per pixel, row-major (empty without alpha).
    const std::vector<float>& alpha() const { return alpha_; }
    float* alphaData() { return alpha_.data(); }
    /// Copies a w × h block of RGB floats (and, with an alpha plane, w × h alphas) to (x, y).
    void setTile(int x, int y, int w, int h, const float* src, const float* alpha = nullptr);
    /// An exact background (Scene::exactBackground): the image has an alpha plane, its colour
    /// is premultiplied by it, and the 8-bit picture lays it over this linear colour, which is
    /// neither exposed nor tone-mapped (toRgb8).
    void setBackdrop(const Color& linear) {
        backdrop_ = linear;
        hasBackdrop_ = true;
    }
    bool hasBackdrop() const { return hasBackdrop_; }
    const Color& backdrop() const { return backdrop_; }

private:
    int w_ = 0, h_ = 0;
    std::vector<float> rgb_;
    std::vector<float> alpha_;
    Color backdrop_{0.f};
    bool hasBackdrop_ = false;
};

/// sRGB transfer function (IEC 61966-2-1) for linear values in [0, 1].
float srgbEncode(float linear);
/// Inverse of srgbEncode.
float srgbDecode(float encoded);
/// Tone mapping of one linear channel: clamp to [0, 1], or x/(1+x). NaN maps to 0.
float toneMap(float x, ToneMap op);
/// [0, 1] → 0..255 with rounding; NaN and negatives give 0, +Inf and > 1 give 255.
uint8_t toByte(float v);
/// toByte(srgbEncode(v)) for any float, by a table of the 255 thresholds between bytes: the same
/// byte, without a pow.
uint8_t srgbByte(float v);

/// Khronos PBR Neutral of a linear colour: unchanged below 0.76 (but for a small black offset),
/// highlights rolled off towards white along the colour's own hue. Result in [0, 1].
Color pbrNeutral(Color c);
/// 2^ev, the factor --exposure EV applies to radiance.
float exposureScale(float ev);

/// The one 8-bit conversion: scales n linear values (RGB triples) by `scale` (2^EV), tone-maps,
/// sRGB-encodes and rounds them into out. Clamp and Reinhard map each channel; PBR Neutral maps
/// the colour.
void encodeRgb8(const float* rgb, size_t n, ToneMap op, uint8_t* out, float scale = 1.f);
/// One pixel of premultiplied linear colour and coverage a laid over an exact background: the
/// model's colour (divided by a, scaled by `scale`, tone-mapped) and the backdrop (linear,
/// neither scaled nor tone-mapped) mixed by a in linear light, then sRGB-encoded. a = 1 gives
/// encodeRgb8's bytes; a = 0 the backdrop's own bytes (srgbByte of each channel).
void toRgb8OverPixel(const float* rgb, float a, ToneMap op, const Color& backdrop, uint8_t* out, float scale = 1.f);
/// Tone-maps and sRGB-encodes a linear image to 8-bit RGB (encodeRgb8 over the image; an image
/// with a backdrop is laid over it, toRgb8OverPixel).
std::vector<uint8_t> toRgb8(const Image& img, ToneMap op, float scale = 1.f);
/// The same with the tone map and exposure of settings.
std::vector<uint8_t> toRgb8(const Image& img, const RenderSettings& s);
/// One pixel of premultiplied linear colour and coverage a to 8-bit straight (unassociated)
/// RGBA, as PNG, VP9 and ProRes carry it: the colour is divided by a before tone mapping, and
/// scaled by `scale` (2^EV).
void toRgba8Pixel(const float* rgb, float a, ToneMap op, uint8_t* out, float scale = 1.f);
/// The whole image to 8-bit straight RGBA (alpha 255 where the image has no alpha plane).
std::vector<uint8_t> toRgba8(const Image& img, ToneMap op, float scale = 1.f);

/// 8-bit RGB (channels 3) or straight RGBA (channels 4) as PNG bytes ("" if it cannot be encoded).
std::string encodePng(int width, int height, const std::vector<uint8_t>& pixels, int channels);
/// Writes 8-bit RGB (channels 3) or straight RGBA (channels 4) as PNG; throws
/// std::runtime_error naming the path on failure.
void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& pixels, int channels = 3);
/// Reads a PNG (or any stb-readable image) as 8-bit RGB; throws naming the path on failure.
std::vector<uint8_t> readImageRgb8(const std::string& path, int& width, int& height);
/// The image file's size from its header alone (nothing decoded); false if it is no image stb reads.
bool readImageSize(const std::string& path, int& width, int& height);
/// The same with `channels` (3: RGB, 4: RGBA) per pixel.
std::vector<uint8_t> readImage8(const std::string& path, int& width, int& height, int channels);

}  // namespace rf
