#include "engine/lights/environment.h"

#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfCheckFile.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <stb_image.h>

#include <cstring>

#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/util/parallel.h"

namespace rf {

namespace {

/// atan2(y, x) in [−π, π] to about 4e-7 rad: the octant's ratio t ∈ [0, 1] through the odd
/// polynomial of Abramowitz & Stegun 4.4.49 (|error| ≤ 2e-8 for atan t), then the octant's
/// reflections, signed zeros as libm's (atan2(±0, +0) = ±0, atan2(±0, −0) = ±π). libm's atan2f
/// and acosf were 8% of a glTF turntable's CPU time, two of each per shading point (the
/// environment's diffuse and specular look-ups).
/// The octant's arc tangent and its reflections, for one float or four lanes (the same
/// operations in the same order, so a lane's result is the scalar's bit for bit). t = lo/hi in
/// [0, 1]; steep, left: 1 where |y| > |x| and where x's sign bit is set, else 0.
template <typename T>
T atan2Reflected(T t, T steep, T left) {
    const T t2 = t * t;
    const T p = ((((((((0.0028662257f * t2 - 0.0161657367f) * t2 + 0.0429096138f) * t2 - 0.0752896400f) * t2 +
                     0.1065626393f) * t2 - 0.1420889944f) * t2 + 0.1999355085f) * t2 - 0.3333314528f) * t2 + 1.f);
    // The reflections by arithmetic, not branches: directions come in no order a predictor
    // learns. a → π/2 − a past the diagonal, then a → π − a for x < 0 (−0 too, as libm:
    // atan2(+0, −0) = π).
    T a = p * t;
    a += steep * (0.5f * kPi - 2.f * a);
    a += left * (kPi - 2.f * a);
    return a;
}

float atan2Approx(float y, float x) {
    const float ax = std::abs(x), ay = std::abs(y);
    const float hi = std::max(ax, ay), lo = std::min(ax, ay);
    if (std::isnan(x) || std::isnan(y)) return x + y;  // NaN in, NaN out, as libm
    const float t = hi > 0.f ? lo / hi : 0.f;  // a select, not a branch; exact for denormals too
    uint32_t xBits;
    std::memcpy(&xBits, &x, sizeof xBits);
    return std::copysign(atan2Reflected(t, float(ay > ax), float(xBits >> 31)), y);
}

constexpr int kSignBit = int(0x80000000u);

/// atan2Approx in four lanes, for lanes without NaN (the caller takes those one by one).
F4 atan2Approx4(F4 y, F4 x) {
    const I4 sign = splatI4(kSignBit);
    const F4 ax = reinterpret_cast<F4>(reinterpret_cast<I4>(x) & ~sign);
    const F4 ay = reinterpret_cast<F4>(reinterpret_cast<I4>(y) & ~sign);
    const I4 steep = ay > ax;
    const F4 hi = steep ? ay : ax, lo = steep ? ax : ay;  // std::max and std::min without NaN
    const F4 zero = splat4(0.f), one = splat4(1.f);
    const F4 t = hi > zero ? lo / hi : zero;
    const F4 left = (reinterpret_cast<I4>(x) & sign) != 0 ? one : zero;
    const F4 a = atan2Reflected(t, steep ? one : zero, left);
    return reinterpret_cast<F4>((reinterpret_cast<I4>(a) & ~sign) | (reinterpret_cast<I4>(y) & sign));
}

}  // namespace

Vec2 equirectUv(const Vec3& d) {
    const float u = 0.5f + atan2Approx(d.z, d.x) * (0.5f / kPi);
    // acos(d.y) of a unit d, as the angle from +Y: better conditioned near the poles than acos.
    const float v = atan2Approx(std::sqrt(d.x * d.x + d.z * d.z), d.y) * (1.f / kPi);
    return Vec2(u, v);
}

Vec3 equirectDirection(Vec2 uv) {
    const float phi = (uv.x - 0.5f) * 2.f * kPi, theta = uv.y * kPi;
    const float s = std::sin(theta);
    return Vec3(s * std::cos(phi), std::cos(theta), s * std::sin(phi));
}

namespace {
/// The lower half's fold between the octahedron and the square's corners: its own inverse.
void octahedralFold(float& px, float& pz) {
    const float fx = 1.f - std::abs(pz), fz = 1.f - std::abs(px);
    px = std::copysign(fx, px);
    pz = std::copysign(fz, pz);
}
}  // namespace

bool equirectUv4(const F4 d[3], F4& u, F4& v) {
    if (laneMask((d[0] != d[0]) | (d[1] != d[1]) | (d[2] != d[2])) != 0) return false;
    u = 0.5f + atan2Approx4(d[2], d[0]) * (0.5f / kPi);
    v = atan2Approx4(sqrt4(d[0] * d[0] + d[2] * d[2]), d[1]) * (1.f / kPi);
    return true;
}

Vec2 octahedralUv(const Vec3& d) {
    const float l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    float px = d.x / l1, pz = d.z / l1;
    if (d.y < 0.f) octahedralFold(px, pz);  // the lower half folds out over the four corners
    return Vec2(0.5f * px + 0.5f, 0.5f * pz + 0.5f);
}

Vec3 octahedralDirection(Vec2 uv) {
    float px = 2.f * uv.x - 1.f, pz = 2.f * uv.y - 1.f;
    const float y = 1.f - std::abs(px) - std::abs(pz);
    if (y < 0.f) octahedralFold(px, pz);
    return glm::normalize(Vec3(px, y, pz));
}

OctahedralImage OctahedralImage::build(int size, int threads, const std::function<Color(const Vec3&)>& f) {
    OctahedralImage img;
    img.size = std::max(1, size);
    const int n = img.size, stride = n + 2;
    img.texels.assign(size_t(stride) * stride, Color(0.f));
    parallelFor(n, threads, [&](int y, int) {
        for (int x = 0; x < n; ++x)
            img.texels[size_t(y + 1) * stride + size_t(x + 1)] = f(octahedralDirection(Vec2((x + 0.5f) / n, (y + 0.5f) / n)));
    });
    // Past an edge the square continues mirrored: (−1, j) is (0, n − 1 − j), and likewise for
    // the other edges; a corner takes both steps, landing on the opposite corner's texel.
    for (int y = -1; y <= n; ++y)
        for (int x = -1; x <= n; ++x) {
            if (x >= 0 && x < n && y >= 0 && y < n) continue;
            int sx = x, sy = y;
            if (sx < 0 || sx >= n) sx = sx < 0 ? 0 : n - 1, sy = n - 1 - sy;
            if (sy < 0 || sy >= n) sy = sy < 0 ? 0 : n - 1, sx = n - 1 - sx;
            img.texels[size_t(y + 1) * stride + size_t(x + 1)] = img.texels[size_t(sy + 1) * stride + size_t(sx + 1)];
        }
    return img;
}

Color OctahedralImage::sample(const Vec3& d) const {
    if (size <= 0) return Color(0.f);
    const Vec2 uv = octahedralUv(d);
    // Texel i's centre sits at (i + 0.5)/size and is stored at i + 1, so the border makes every
    // bilinear footprint of [0, 1]² whole. NaN fails both tests and lands on the first texel.
    float x = uv.x * float(size) + 0.5f, y = uv.y * float(size) + 0.5f;
    if (!(x >= 0.5f)) x = 0.5f;
    if (!(x <= float(size) + 0.5f)) x = float(size) + 0.5f;
    if (!(y >= 0.5f)) y = 0.5f;
    if (!(y <= float(size) + 0.5f)) y = float(size) + 0.5f;
    const int x0 = int(x), y0 = int(y);  // ≤ size, so x0 + 1 is still inside the border
    const float tx = x - float(x0), ty = y - float(y0);
    const size_t stride = size_t(size) + 2;
    const Color* row0 = &texels[size_t(y0) * stride + size_t(x0)];
    const Color* row1 = row0 + stride;
    return (1.f - ty) * ((1.f - tx) * row0[0] + tx * row0[1]) + ty * ((1.f - tx) * row1[0] + tx * row1[1]);
}

namespace {
/// Bilinear weights of four texels, per channel or per lane (the same operation order).
template <typename T>
T bilinear(T c00, T c10, T c01, T c11, T tx, T ty) {
    return (1.f - ty) * ((1.f - tx) * c00 + tx * c10) + ty * ((1.f - tx) * c01 + tx * c11);
}
}  // namespace

void EquirectImage::sample4(F4 u, F4 v, Color out[4]) const {
    const I4 finite = (u - u == splat4(0.f)) & (v - v == splat4(0.f));  // inf − inf and NaN are NaN
    if (width <= 0 || height <= 0 || laneMask(finite) != 0xF) {
        for (int i = 0; i < 4; ++i) out[i] = sample(Vec2(u[i], v[i]));
        return;
    }
    const F4 x = (u - floor4(u)) * float(width) - 0.5f;
    const F4 yRaw = v * float(height) - 0.5f;
    const F4 yHi = splat4(float(height - 1));
    const F4 y = yRaw < splat4(0.f) ? splat4(0.f) : (yHi < yRaw ? yHi : yRaw);  // std::clamp's order
    const F4 fx = floor4(x);
    const I4 ix = __builtin_convertvector(fx, I4), iy = __builtin_convertvector(y, I4);
    const F4 tx = x - fx, ty = y - __builtin_convertvector(iy, F4);
    F4 c[4][3];  // the four texels' channels, lane by lane
    for (int i = 0; i < 4; ++i) {
        int x0 = ix[i];
        if (x0 < 0) x0 += width;
        if (x0 >= width) x0 -= width;
        const int x1 = x0 + 1 < width ? x0 + 1 : 0;
        const int y0 = iy[i], y1 = std::min(y0 + 1, height - 1);
        const Color* t[4] = {&at(x0, y0), &at(x1, y0), &at(x0, y1), &at(x1, y1)};
        for (int k = 0; k < 4; ++k)
            for (int ch = 0; ch < 3; ++ch) c[k][ch][i] = (*t[k])[ch];
    }
    for (int ch = 0; ch < 3; ++ch) {
        const F4 r = bilinear(c[0][ch], c[1][ch], c[2][ch], c[3][ch], tx, ty);
        for (int i = 0; i < 4; ++i) out[i][ch] = r[i];
    }
}

Color EquirectImage::sample(Vec2 uv) const {
    if (width <= 0 || height <= 0) return Color(0.f);
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return at(0, 0);
    const float x = (uv.x - std::floor(uv.x)) * width - 0.5f;  // in [−0.5, width − 0.5]
    const float y = std::clamp(uv.y * height - 0.5f, 0.f, float(height - 1));
    const float fx = std::floor(x);
    // Columns wrap around the seam (no integer division: three of them were a third of a look-up).
    int x0 = int(fx);
    if (x0 < 0) x0 += width;
    if (x0 >= width) x0 -= width;
    const int x1 = x0 + 1 < width ? x0 + 1 : 0;
    const int y0 = int(y), y1 = std::min(y0 + 1, height - 1);
    const float tx = x - fx, ty = y - float(y0);
    return bilinear(at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1), Color(tx), Color(ty));
}

EquirectImage EquirectImage::halved() const {
    EquirectImage h;
    h.width = std::max(1, width / 2);
    h.height = std::max(1, height / 2);
    h.texels.resize(size_t(h.width) * h.height);
    for (int y = 0; y < h.height; ++y) {
        if (y % 64 == 0) pollLoadCancel();
        for (int x = 0; x < h.width; ++x) {
            const int xa = std::min(2 * x, width - 1), xb = std::min(2 * x + 1, width - 1);
            const int ya = std::min(2 * y, height - 1), yb = std::min(2 * y + 1, height - 1);
            h.texels[size_t(y) * h.width + x] = 0.25f * (at(xa, ya) + at(xb, ya) + at(xa, yb) + at(xb, yb));
        }
    }
    return h;
}

namespace {

/// OpenEXR reads from this view of the file's bytes (rank 0 read them; workers got them in the
/// broadcast bundle).
class MemoryStream : public Imf::IStream {
public:
    MemoryStream(const std::string& bytes, const std::string& name) : Imf::IStream(name.c_str()), bytes_(bytes) {}
    bool read(char c[], int n) override {
        if (n < 0 || pos_ + uint64_t(n) > bytes_.size()) throw std::runtime_error("unexpected end of file");
        std::memcpy(c, bytes_.data() + pos_, size_t(n));
        pos_ += uint64_t(n);
        return true;
    }
    uint64_t tellg() override { return pos_; }
    void seekg(uint64_t pos) override { pos_ = pos; }

private:
    const std::string& bytes_;
    uint64_t pos_ = 0;
};

void checkSize(long long w, long long h, const std::string& path) {
    if (w <= 0 || h <= 0) throw InputError(path, "environment image has no pixels");
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    if (w * h > kMaxEnvironmentPixels) throw InputError(path, "environment image of " + size + " is over the limit of 8192x4096 pixels");
    // From the header, before any pixel is decoded: an equirect is 2:1, and nothing far from it
    // maps the sphere (a strip of 8 x 4,194,304 texels is not a panorama).
    if (std::max(w, h) > kMaxEnvironmentAspect * std::min(w, h))
        throw InputError(path, "environment image of " + size + " is not an equirectangular panorama (expected about 2:1; refused past " +
                                   std::to_string(kMaxEnvironmentAspect) + ":1 either way)");
}

EquirectImage decodeExr(const std::string& bytes, const std::string& path) {
    // OpenEXR's own validator first: it walks every part of the file with memory and time
    // limits, so a corrupt file is refused here rather than met half-way through decoding.
    // (Its OpenEXRCore pass is left off: in OpenEXR 3.1 it reports valid DWAB files as bad.)
    if (Imf::checkOpenEXRFile(bytes.data(), bytes.size(), true, true, false))
        throw InputError(path, "not a readable OpenEXR file (corrupt or truncated)");
    EquirectImage img;
    try {
        MemoryStream stream(bytes, path);
        Imf::RgbaInputFile file(stream);
        const Imath::Box2i dw = file.dataWindow();
        const long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
        checkSize(w, h, path);
        Imf::Array2D<Imf::Rgba> px(h, w);
        file.setFrameBuffer(&px[0][0] - dw.min.x - dw.min.y * w, 1, size_t(w));
        file.readPixels(dw.min.y, dw.max.y);
        img.width = int(w);
        img.height = int(h);
        img.texels.resize(size_t(w * h));
        for (long long y = 0; y < h; ++y)
            for (long long x = 0; x < w; ++x) {
                const Imf::Rgba& p = px[y][x];
                img.texels[size_t(y * w + x)] = Color(float(p.r), float(p.g), float(p.b));
            }
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(path, std::string("cannot read OpenEXR file: ") + e.what());
    }
    return img;
}

/// stb fills a truncated Radiance file with black instead of failing, so walk the pixel data
/// first: the header ends at an empty line and the resolution line; then each scanline is
/// either run-length encoded (2, 2, width, then four channels of runs) or flat RGBE.
bool hdrDataComplete(const std::string& bytes, int w, int h) {
    size_t p = bytes.find("\n\n");
    if (p == std::string::npos) return false;
    p = bytes.find('\n', p + 2);  // the "-Y h +X w" line
    if (p == std::string::npos) return false;
    ++p;
    const size_t n = bytes.size();
    auto byte = [&](size_t i) { return static_cast<unsigned char>(bytes[i]); };
    for (int y = 0; y < h; ++y) {
        if (p + 4 > n) return false;
        const bool rle = w >= 8 && w < 32768 && byte(p) == 2 && byte(p + 1) == 2 && !(byte(p + 2) & 0x80);
        if (!rle) {  // flat (or old-style) pixels: stb reads the rest of the image as 4 bytes each
            return n - p >= size_t(w) * size_t(h - y) * 4;
        }
        if (((byte(p + 2) << 8) | byte(p + 3)) != w) return false;
        p += 4;
        for (int c = 0; c < 4; ++c)
            for (int x = 0; x < w;) {
                if (p >= n) return false;
                int count = byte(p++);
                if (count > 128) {
                    count -= 128;
                    if (p + 1 > n) return false;
                    p += 1;
                } else {
                    if (count == 0 || p + size_t(count) > n) return false;
                    p += size_t(count);
                }
                x += count;
                if (x > w) return false;
            }
    }
    return true;
}

EquirectImage decodeHdr(const std::string& bytes, const std::string& path) {
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    if (bytes.size() > size_t(INT32_MAX)) throw InputError(path, "environment file over 2 GiB");
    const int len = int(bytes.size());
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(data, len, &w, &h, &comp)) throw InputError(path, "not a readable Radiance .hdr file");
    checkSize(w, h, path);
    if (!hdrDataComplete(bytes, w, h)) throw InputError(path, "Radiance .hdr file is truncated or its pixel data malformed");
    float* px = stbi_loadf_from_memory(data, len, &w, &h, &comp, 3);
    if (!px) throw InputError(path, std::string("cannot read Radiance .hdr file (") + stbi_failure_reason() + ")");
    EquirectImage img;
    img.width = w;
    img.height = h;
    img.texels.resize(size_t(w) * h);
    for (size_t i = 0; i < img.texels.size(); ++i) img.texels[i] = Color(px[3 * i], px[3 * i + 1], px[3 * i + 2]);
    stbi_image_free(px);
    return img;
}

}  // namespace

EquirectImage decodeEnvironment(const std::string& bytes, const std::string& path) {
    static const char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
    EquirectImage img;
    if (bytes.size() >= 4 && std::memcmp(bytes.data(), kExrMagic, 4) == 0) img = decodeExr(bytes, path);
    else if (bytes.rfind("#?", 0) == 0) img = decodeHdr(bytes, path);
    else throw InputError(path, "not an environment image (expected an equirectangular .hdr or .exr)");
    for (size_t i = 0; i < img.texels.size(); ++i) {
        if (i % (1 << 20) == 0) pollLoadCancel();
        Color& c = img.texels[i];
        if (!isFinite(c)) throw InputError(path, "environment image holds non-finite radiance");
        c = glm::max(c, Color(0.f));  // lossy compression (DWA) rings slightly below zero
    }
    return img;
}

namespace {

/// A soft rectangular light on the sphere: smooth falloff around (azimuth, elevation).
float softBox(const Vec3& d, float azimuthDeg, float elevationDeg, float sizeDeg) {
    const float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    const Vec3 c(std::cos(el) * std::cos(az), std::sin(el), std::cos(el) * std::sin(az));
    const float angle = std::acos(std::clamp(glm::dot(d, c), -1.f, 1.f));
    const float x = angle / glm::radians(sizeDeg);
    return x >= 1.f ? 0.f : (1.f - x * x) * (1.f - x * x);
}

}  // namespace

EquirectImage builtinStudioEnvironment(int width) {
    EquirectImage img;
    img.width = std::max(8, width);
    img.height = img.width / 2;
    img.texels.resize(size_t(img.width) * img.height);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const Vec3 d = equirectDirection(Vec2((x + 0.5f) / img.width, (y + 0.5f) / img.height));
            // Walls: a grey gradient, brighter towards the top; floor: a warm dim bounce.
            Color c = d.y >= 0.f ? glm::mix(Color(0.30f, 0.31f, 0.33f), Color(0.55f, 0.56f, 0.58f), d.y)
                                 : glm::mix(Color(0.22f, 0.20f, 0.18f), Color(0.12f, 0.11f, 0.10f), -d.y);
            c += Color(4.0f) * softBox(d, 0.f, 90.f, 35.f);                      // overhead
            c += Color(9.0f, 8.6f, 8.0f) * softBox(d, 135.f, 30.f, 18.f);        // key
            c += Color(5.0f, 5.4f, 6.0f) * softBox(d, -45.f, 20.f, 14.f);        // rim
            img.texels[size_t(y) * img.width + x] = c;
        }
    return img;
}

}  // namespace rf
