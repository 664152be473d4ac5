#include "engine/scene/env_lighting.h"

#include "engine/materials/brdf_gltf.h"
#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/util/parallel.h"
#include "engine/scene/scene.h"

namespace rf {

namespace {

size_t pixelsOf(const EquirectImage& img) { return size_t(img.width) * size_t(img.height); }

/// The mip chain ends at or below this many pixels.
constexpr size_t kSmallLevelPixels = 8192;
/// The irradiance sums a level of at most this many pixels.
constexpr size_t kIrradiancePixels = 65536;

/// Solid angle of texel row y of a w × h equirect.
float texelSolidAngle(int y, int w, int h) {
    const float theta = (y + 0.5f) / h * kPi;
    return (2.f * kPi / w) * (kPi / h) * std::sin(theta);
}

/// Radiance at uv, read from the mip level whose texels match a footprint of `lod` (0: full).
Color sampleMips(const std::vector<EquirectImage>& mips, Vec2 uv, float lod) {
    lod = std::clamp(lod, 0.f, float(mips.size() - 1));
    const int l0 = int(lod);
    const int l1 = std::min(l0 + 1, int(mips.size()) - 1);
    const float t = lod - float(l0);
    const Color a = mips[size_t(l0)].sample(uv);
    return t > 0.f ? glm::mix(a, mips[size_t(l1)].sample(uv), t) : a;
}

/// E(n)/π over a small copy of the radiance, by summing every texel: exact for that copy, and
/// no ringing (spherical harmonics ring around bright, small lights).
OctahedralImage convolveIrradiance(const EquirectImage& src, int threads) {
    std::vector<Vec3> dirs(src.texels.size());
    std::vector<Color> weighted(src.texels.size());
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x) {
            const size_t i = size_t(y) * src.width + x;
            dirs[i] = equirectDirection(Vec2((x + 0.5f) / src.width, (y + 0.5f) / src.height));
            weighted[i] = src.texels[i] * (texelSolidAngle(y, src.width, src.height) / kPi);
        }
    // 24² texels: about the 32 × 16 of an equirect, evenly spread.
    return OctahedralImage::build(24, threads, [&](const Vec3& n) {
        pollLoadCancel();
        Color sum(0.f);
        for (size_t i = 0; i < dirs.size(); ++i) sum += weighted[i] * std::max(0.f, glm::dot(n, dirs[i]));
        return sum;
    });
}

/// The radiance prefiltered by GGX at one roughness, with n = v = r (the split-sum
/// assumption). Deterministic Hammersley samples read mip levels matched to each sample's
/// share of the lobe (Křivánek and Colbert 2008), so the result is smooth, not noisy.
OctahedralImage prefilterSpecular(const std::vector<EquirectImage>& mips, float roughness, int size, int threads) {
    constexpr uint32_t kSamples = 128;
    const float alpha = std::max(pbr::alphaFromRoughness(roughness), 1e-3f);
    const EquirectImage& top = mips.front();
    const float texel = 4.f * kPi / (float(top.width) * float(top.height));
    return OctahedralImage::build(size, threads, [&](const Vec3& r) {
        pollLoadCancel();
        Vec3 t, b;
        orthonormalBasis(r, t, b);
        Color sum(0.f);
        float weight = 0.f;
        for (uint32_t i = 0; i < kSamples; ++i) {
            const Vec2 u = pbr::hammersley(i, kSamples);
            const Vec3 hl = pbr::sampleGgxHalfVector(alpha, u.x, u.y);
            const Vec3 h = hl.x * t + hl.y * b + hl.z * r;
            const float rh = glm::dot(r, h);
            const Vec3 l = 2.f * rh * h - r;
            const float nl = glm::dot(r, l);
            if (nl <= 0.f) continue;
            // pdf(l) = D·(n·h)/(4 v·h) = D/4 here; the sample covers 1/(N·pdf) steradians.
            const float pdf = pbr::ggxD(hl.z, alpha) * 0.25f;
            const float lod = 0.5f * std::log2(1.f / (kSamples * pdf * texel)) + 1.f;
            sum += sampleMips(mips, equirectUv(l), lod) * nl;
            weight += nl;
        }
        return weight > 0.f ? sum / weight : Color(0.f);
    });
}

}  // namespace

EnvironmentLight::EnvironmentLight(EquirectImage radiance, float rotationDeg, float intensity, int threads) {
    const float rot = glm::radians(std::isfinite(rotationDeg) ? rotationDeg : 0.f);
    cosRot_ = std::cos(rot);
    sinRot_ = std::sin(rot);
    if (intensity != 1.f)
        for (Color& c : radiance.texels) c *= intensity;
    LoadStep step("filtering the environment");
    mips_.push_back(std::move(radiance));
    // Down to about 8x4; an image whose short side gets there first (a tall or wide strip) goes
    // on halving its long side until its pixels are few too. Stopping at the short side alone
    // left an 8 x 4,194,304 image with no smaller level, and the irradiance below summed all
    // 33.5 million texels for each of its 576: 70 s against 1.7 s at 2:1.
    while ((mips_.back().width > 8 && mips_.back().height > 4) || pixelsOf(mips_.back()) > kSmallLevelPixels)
        mips_.push_back(mips_.back().halved());
    // A copy about 128 texels wide is fine enough for a cosine lobe; one of a strange shape is
    // also kept to few pixels (1:4 at 128 wide is 65,536: every accepted shape keeps its level).
    size_t small = 0;
    while (small + 1 < mips_.size() && (mips_[small].width > 128 || pixelsOf(mips_[small]) > kIrradiancePixels)) ++small;
    irradianceSourcePixels_ = pixelsOf(mips_[small]);
    irradiance_ = convolveIrradiance(mips_[small], threads);
    for (int k = 1; k < kLevels; ++k) {
        // As many texels as the equirect of width w this replaced: w²/2 = size².
        const int width = std::clamp(mips_.front().width >> (k + 1), 32, 256);
        const int size = int(std::lround(width * 0.70710678));
        specular_.push_back(prefilterSpecular(mips_, float(k) / (kLevels - 1), size, threads));
    }
}

size_t EnvironmentLight::mipPixels() const {
    size_t n = 0;
    for (size_t i = 1; i < mips_.size(); ++i) n += pixelsOf(mips_[i]);
    return n;
}

Vec3 EnvironmentLight::toMap(const Vec3& d) const {
    // The map is turned by +angle about +Y, so a world direction reads the map turned by −angle.
    return Vec3(cosRot_ * d.x - sinRot_ * d.z, d.y, sinRot_ * d.x + cosRot_ * d.z);
}

Color EnvironmentLight::radiance(const Vec3& d) const { return mips_.front().sample(equirectUv(toMap(d))); }

void EnvironmentLight::radiance4(const Vec3 d[4], Color out[4]) const {
    // toMap lane by lane.
    const F4 x{d[0].x, d[1].x, d[2].x, d[3].x}, y{d[0].y, d[1].y, d[2].y, d[3].y}, z{d[0].z, d[1].z, d[2].z, d[3].z};
    const F4 m[3] = {cosRot_ * x - sinRot_ * z, y, sinRot_ * x + cosRot_ * z};
    F4 u, v;
    if (!equirectUv4(m, u, v)) {
        for (int i = 0; i < 4; ++i) out[i] = radiance(d[i]);
        return;
    }
    mips_.front().sample4(u, v, out);
}

Color EnvironmentLight::diffuse(const Vec3& n) const { return irradiance_.sample(toMap(n)); }

Color EnvironmentLight::specular(const Vec3& r, float roughness) const {
    const Vec3 d = toMap(r);
    const float level = std::clamp(std::isfinite(roughness) ? roughness : 1.f, 0.f, 1.f) * (kLevels - 1);
    const int l0 = int(level);  // the top level (roughness 1) is one look-up, not a mix
    const float t = level - float(l0);
    const Color a = l0 == 0 ? mips_.front().sample(equirectUv(d)) : specular_[size_t(l0 - 1)].sample(d);
    return t > 0.f ? glm::mix(a, specular_[size_t(l0)].sample(d), t) : a;
}

std::shared_ptr<const EnvironmentLight> loadEnvironment(const EnvironmentSpec& spec, FileSource& fs) {
    if (!std::isfinite(spec.rotationDeg)) throw InputError(spec.file, "environment rotation is not a finite number");
    if (!(spec.intensity >= 0.f) || !std::isfinite(spec.intensity))
        throw InputError(spec.file.empty() ? "environment" : spec.file, "environment intensity must be a finite number >= 0");
    LoadStep step("decoding the environment");
    EquirectImage img = spec.file.empty() ? builtinStudioEnvironment()
                                          : decodeEnvironment(fs.read(spec.file, kMaxEnvironmentBytes), spec.file);
    return std::make_shared<const EnvironmentLight>(std::move(img), spec.rotationDeg, spec.intensity);
}

void attachEnvironment(Scene& scene, const std::optional<EnvironmentSpec>& own, const SceneOptions& options, FileSource& fs) {
    std::optional<EnvironmentSpec> spec = options.environment ? options.environment : own;
    if (!spec) return;
    if (options.environmentRotation) spec->rotationDeg = *options.environmentRotation;
    if (options.environmentIntensity) spec->intensity = *options.environmentIntensity;
    scene.environment = loadEnvironment(*spec, fs);
    scene.environmentSource = *spec;
    scene.environmentBackground = true;
}

}  // namespace rf
