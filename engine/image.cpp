#include "image.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

// Debian builds stb as a shared library (libstb), so no *_IMPLEMENTATION here.
#include <stb_image.h>
#include <stb_image_write.h>

#include "file_write.h"

namespace rf {

void Image::setTile(int x, int y, int w, int h, const float* src, const float* alpha) {
    for (int j = 0; j < h; ++j) std::memcpy(pixel(x, y + j), src + size_t(j) * w * 3, sizeof(float) * 3 * w);
    if (alpha && hasAlpha())
        for (int j = 0; j < h; ++j)
            std::memcpy(&alpha_[size_t(y + j) * w_ + x], alpha + size_t(j) * w, sizeof(float) * w);
}

float srgbEncode(float v) {
    if (!(v > 0.f)) return 0.f;
    if (v >= 1.f) return 1.f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}

float srgbDecode(float v) {
    if (!(v > 0.f)) return 0.f;
    if (v >= 1.f) return 1.f;
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float toneMap(float x, ToneMap op) {
    if (std::isnan(x) || x <= 0.f) return 0.f;
    if (op == ToneMap::Clamp) return x >= 1.f ? 1.f : x;
    if (std::isinf(x)) return 1.f;
    return x / (1.f + x);
}

uint8_t toByte(float v) {
    if (!(v > 0.f)) return 0;  // NaN, −0, negatives
    if (!(v < 1.f)) return 255;
    return static_cast<uint8_t>(v * 255.f + 0.5f);
}

namespace {

/// The one display mapping of a linear value: tone map, sRGB encode, round to a byte.
uint8_t encodeChannel(float linear, ToneMap op) { return toByte(srgbEncode(toneMap(linear, op))); }

}  // namespace

void encodeRgb8(const float* linear, size_t n, ToneMap op, uint8_t* out) {
    for (size_t i = 0; i < n; ++i) out[i] = encodeChannel(linear[i], op);
}

std::vector<uint8_t> toRgb8(const Image& img, ToneMap op) {
    const size_t n = size_t(img.width()) * img.height() * 3;
    std::vector<uint8_t> out(n);
    encodeRgb8(img.data(), n, op, out.data());
    return out;
}

void toRgba8Pixel(const float* rgb, float a, ToneMap op, uint8_t* out) {
    const uint8_t alpha = toByte(a);
    // Below half a step of alpha the pixel is transparent: its colour carries no meaning, and
    // dividing by a tiny coverage would only amplify noise.
    const float inv = alpha == 0 ? 0.f : 1.f / a;
    for (int k = 0; k < 3; ++k) out[k] = encodeChannel(rgb[k] * inv, op);
    out[3] = alpha;
}

std::vector<uint8_t> toRgba8(const Image& img, ToneMap op) {
    const size_t n = size_t(img.width()) * img.height();
    std::vector<uint8_t> out(n * 4);
    const float* src = img.data();
    for (size_t i = 0; i < n; ++i) toRgba8Pixel(src + 3 * i, img.hasAlpha() ? img.alpha()[i] : 1.f, op, &out[4 * i]);
    return out;
}

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& pixels, int channels) {
    // Encoded in memory, then written with every write checked: stb's own file writer ignores
    // fwrite errors, so a full disk used to leave an empty PNG behind a success message.
    std::string png;
    auto append = [](void* out, void* data, int size) { static_cast<std::string*>(out)->append(static_cast<const char*>(data), size_t(size)); };
    if (!stbi_write_png_to_func(append, &png, width, height, channels, pixels.data(), width * channels))
        throw std::runtime_error(path + ": cannot encode PNG");
    writeFileChecked(path, png);
}

std::vector<uint8_t> readImageRgb8(const std::string& path, int& width, int& height) {
    return readImage8(path, width, height, 3);
}

std::vector<uint8_t> readImage8(const std::string& path, int& width, int& height, int channels) {
    int comp = 0;
    unsigned char* data = stbi_load(path.c_str(), &width, &height, &comp, channels);
    if (!data) throw std::runtime_error(path + ": cannot read image (" + stbi_failure_reason() + ")");
    std::vector<uint8_t> out(data, data + size_t(width) * height * channels);
    stbi_image_free(data);
    return out;
}

}  // namespace rf
