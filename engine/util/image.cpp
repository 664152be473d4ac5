#include "engine/util/image.h"

#include <cmath>
#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

// Debian builds stb as a shared library (libstb), so no *_IMPLEMENTATION here.
#include <stb_image.h>
#include <stb_image_write.h>

#include "engine/util/file_write.h"
#include "engine/util/simd4.h"

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

/// The sRGB byte of a display value by table instead of a pow per channel (a powf is some 12 ns,
/// 7% of a Whitted film's CPU time). step[k] is the least float v with toByte(srgbEncode(v)) ≥
/// k + 1, found by bisection on the float bit patterns of [0, 1] (ordered like the floats), so
/// the byte of v is the number of steps at or below it: the composite is non-decreasing.
/// Counting them is one look-up: the upper 16 bits of v pick a bucket (1/128 of an octave) that
/// holds at most one step (checked here), and bucket[i] is the byte at the bucket's lowest float.
struct SrgbTable {
    float step[256];
    uint8_t bucket[(0x3f800000u >> 16) + 1];
    SrgbTable() {
        for (int k = 1; k <= 255; ++k) {
            uint32_t lo = 0, hi = 0x3f800000u;  // bits of 0 and of 1: toByte(srgbEncode(1)) = 255
            while (lo < hi) {
                const uint32_t mid = lo + (hi - lo) / 2;
                if (toByte(srgbEncode(fromBits(mid))) >= k) hi = mid;
                else lo = mid + 1;
            }
            step[k - 1] = fromBits(lo);
        }
        step[255] = std::numeric_limits<float>::infinity();  // no byte 256
        for (uint32_t i = 0; i < sizeof bucket; ++i) {
            bucket[i] = toByte(srgbEncode(fromBits(i << 16)));
            const float last = fromBits(std::min((i << 16) | 0xffffu, 0x3f800000u));
            if (bucket[i] < 254 && step[bucket[i] + 1] <= last)
                throw std::logic_error("srgbByte: two sRGB steps in one bucket");
        }
    }
    static float fromBits(uint32_t bits) {
        float v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
};

const SrgbTable& srgbTable() {
    static const SrgbTable table;
    return table;
}

/// The byte of v ∈ [0, 1] (v = 1 gives 255): its bucket's byte, plus one past the bucket's step.
inline uint8_t tableByte(const SrgbTable& t, float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    const uint8_t b = t.bucket[bits >> 16];
    return static_cast<uint8_t>(b + (v >= t.step[b]));
}

/// Four pixels' channels, one pixel per lane: the display mapping runs on four at once, and a
/// single pixel runs the same operations in lane 0, so no pixel's bytes depend on its
/// neighbours (a row's tail, an RGBA pixel, a tile edge all give what a whole row would).
struct Rgb4 {
    F4 c[3];
};

inline F4 pick(I4 mask, F4 a, F4 b) { return mask ? a : b; }

/// Khronos PBR Neutral (2024), constants from its specification, lane by lane: both sides of
/// its "below the shoulder" test are computed and one kept.
Rgb4 pbrNeutral4(Rgb4 v) {
    constexpr float kStart = 0.8f - 0.04f, kDesaturation = 0.15f;
    constexpr float d = 1.f - kStart;
    const F4 zero = splat4(0.f);
    for (F4& c : v.c) c = pick(c > zero, pick(splat4(1e30f) < c, splat4(1e30f), c), zero);  // NaN, −, +Inf
    const F4 gb = pick(v.c[2] < v.c[1], v.c[2], v.c[1]);
    const F4 x = pick(gb < v.c[0], gb, v.c[0]);
    const F4 offset = pick(x < splat4(0.08f), x - splat4(6.25f) * x * x, splat4(0.04f));
    for (F4& c : v.c) c -= offset;
    const F4 gb2 = pick(v.c[1] < v.c[2], v.c[2], v.c[1]);
    const F4 peak = pick(v.c[0] < gb2, gb2, v.c[0]);
    const F4 newPeak = splat4(1.f) - splat4(d * d) / (peak + splat4(d) - splat4(kStart));
    const F4 ratio = newPeak / peak;  // a dark lane's 0/0 is discarded below
    const F4 g = splat4(1.f) - splat4(1.f) / (splat4(kDesaturation) * (peak - newPeak) + splat4(1.f));
    const I4 below = peak < splat4(kStart);
    for (F4& c : v.c) c = pick(below, c, (c * ratio) * (splat4(1.f) - g) + newPeak * g);
    return v;
}

/// Four pixels scaled and tone mapped, not yet clamped to [0, 1] (Clamp: the clamp is the whole
/// of it, left to the caller).
Rgb4 toneMapped4(Rgb4 v, ToneMap op, float scale) {
    const F4 s = splat4(scale), zero = splat4(0.f), one = splat4(1.f);
    for (F4& c : v.c) c = c * s;
    if (op == ToneMap::PbrNeutral) {
        v = pbrNeutral4(v);
    } else if (op == ToneMap::Reinhard) {
        for (F4& c : v.c) {
            const I4 inf = c == splat4(kInf);
            c = pick(c > zero, pick(inf, one, c / (one + c)), zero);  // NaN and negatives: 0
        }
    }
    return v;
}

/// Scale, tone map and sRGB bytes of four pixels: channel k of lane i to out[stride·i + k], for
/// the first `lanes` lanes.
void encode4(const SrgbTable& t, Rgb4 v, ToneMap op, float scale, uint8_t* out, int lanes, int stride) {
    const F4 zero = splat4(0.f), one = splat4(1.f);
    v = toneMapped4(v, op, scale);
    for (int k = 0; k < 3; ++k) {
        // NaN and ≤ 0 to 0, ≥ 1 to 1: the byte of 1 is 255.
        const F4 c = pick(v.c[k] > zero, pick(v.c[k] < one, v.c[k], one), zero);
        for (int lane = 0; lane < lanes; ++lane) out[stride * lane + k] = tableByte(t, c[lane]);
    }
}

Rgb4 load4(const float* rgb, int lanes) {
    Rgb4 v{{splat4(0.f), splat4(0.f), splat4(0.f)}};
    for (int lane = 0; lane < lanes; ++lane)
        for (int k = 0; k < 3; ++k) v.c[k][lane] = rgb[3 * lane + k];
    return v;
}

}  // namespace

uint8_t srgbByte(float v) {
    if (!(v > 0.f)) return 0;  // NaN, −0, negatives
    if (!(v < 1.f)) return 255;
    return tableByte(srgbTable(), v);
}

Color pbrNeutral(Color c) {
    const Rgb4 v = pbrNeutral4(load4(&c[0], 1));
    return Color(v.c[0][0], v.c[1][0], v.c[2][0]);
}

float exposureScale(float ev) { return std::exp2(std::clamp(ev, -64.f, 64.f)); }

void encodeRgb8(const float* rgb, size_t n, ToneMap op, uint8_t* out, float scale) {
    const SrgbTable& t = srgbTable();
    const size_t pixels = n / 3;
    size_t i = 0;
    for (; i + 4 <= pixels; i += 4) encode4(t, load4(rgb + 3 * i, 4), op, scale, out + 3 * i, 4, 3);
    if (i < pixels) encode4(t, load4(rgb + 3 * i, int(pixels - i)), op, scale, out + 3 * i, int(pixels - i), 3);
}

void toRgb8OverPixel(const float* rgb, float a, ToneMap op, const Color& backdrop, uint8_t* out, float scale) {
    if (!(a > 0.f)) {  // a miss (or NaN coverage): the backdrop exactly
        for (int k = 0; k < 3; ++k) out[k] = srgbByte(backdrop[k]);
        return;
    }
    if (!(a < 1.f)) {  // wholly the model: the bytes an opaque render gives
        encode4(srgbTable(), load4(rgb, 1), op, scale, out, 1, 3);
        return;
    }
    // An edge: the model's tone-mapped colour (straight, in [0, 1]) mixed with the backdrop.
    const Rgb4 v = toneMapped4(load4(rgb, 1), op, scale / a);
    for (int k = 0; k < 3; ++k) {
        float m = v.c[k][0];
        m = m > 0.f ? std::min(m, 1.f) : 0.f;
        out[k] = srgbByte(a * m + (1.f - a) * backdrop[k]);
    }
}

std::vector<uint8_t> toRgb8(const Image& img, ToneMap op, float scale) {
    const size_t n = size_t(img.width()) * img.height();
    std::vector<uint8_t> out(n * 3);
    if (img.hasBackdrop() && img.hasAlpha()) {
        for (size_t i = 0; i < n; ++i) toRgb8OverPixel(img.data() + 3 * i, img.alpha()[i], op, img.backdrop(), &out[3 * i], scale);
        return out;
    }
    encodeRgb8(img.data(), 3 * n, op, out.data(), scale);
    return out;
}

std::vector<uint8_t> toRgb8(const Image& img, const RenderSettings& s) {
    return toRgb8(img, s.toneMap, exposureScale(s.exposure));
}

void toRgba8Pixel(const float* rgb, float a, ToneMap op, uint8_t* out, float scale) {
    const uint8_t alpha = toByte(a);
    // Below half a step of alpha the pixel is transparent: its colour carries no meaning, and
    // dividing by a tiny coverage would only amplify noise.
    const float inv = alpha == 0 ? 0.f : 1.f / a;
    const float straight[3] = {rgb[0] * inv, rgb[1] * inv, rgb[2] * inv};
    encode4(srgbTable(), load4(straight, 1), op, scale, out, 1, 4);
    out[3] = alpha;
}

std::vector<uint8_t> toRgba8(const Image& img, ToneMap op, float scale) {
    const size_t n = size_t(img.width()) * img.height();
    std::vector<uint8_t> out(n * 4);
    const float* src = img.data();
    for (size_t i = 0; i < n; ++i) toRgba8Pixel(src + 3 * i, img.hasAlpha() ? img.alpha()[i] : 1.f, op, &out[4 * i], scale);
    return out;
}

std::string encodePng(int width, int height, const std::vector<uint8_t>& pixels, int channels) {
    std::string png;
    auto append = [](void* out, void* data, int size) { static_cast<std::string*>(out)->append(static_cast<const char*>(data), size_t(size)); };
    if (!stbi_write_png_to_func(append, &png, width, height, channels, pixels.data(), width * channels)) png.clear();
    return png;
}

void writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& pixels, int channels) {
    // Encoded in memory, then written with every write checked: stb's own file writer ignores
    // fwrite errors, so a full disk used to leave an empty PNG behind a success message.
    const std::string png = encodePng(width, height, pixels, channels);
    if (png.empty()) throw std::runtime_error(path + ": cannot encode PNG");
    writeFileChecked(path, png);
}

std::vector<uint8_t> readImageRgb8(const std::string& path, int& width, int& height) {
    return readImage8(path, width, height, 3);
}

bool readImageSize(const std::string& path, int& width, int& height) {
    int comp = 0;
    return stbi_info(path.c_str(), &width, &height, &comp) != 0;
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
