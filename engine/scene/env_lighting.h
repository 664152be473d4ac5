#pragma once
/// An environment prepared for noise-free shading: the radiance seen directly (background,
/// mirror reflections), its cosine-convolved irradiance for diffuse light, and copies
/// prefiltered by the GGX lobe at a few roughness levels for glossy light (the split sum of
/// Karis 2013; brdf_gltf.h holds the other half). Built once per scene on every rank, from the
/// same bytes, so every rank shades identically.
#include <memory>
#include <vector>

#include <optional>

#include "engine/lights/environment.h"
#include "engine/util/file_source.h"
#include "engine/scene/scene_options.h"

namespace rf {

/// The largest environment image file read (.hdr or .exr).
inline constexpr uint64_t kMaxEnvironmentBytes = 1ull << 30;

class EnvironmentLight {
public:
    /// rotationDeg turns the environment about +Y (positive: +X towards −Z, right-handed);
    /// intensity scales its radiance.
    EnvironmentLight(EquirectImage radiance, float rotationDeg, float intensity, int threads = 0);

    /// Radiance arriving from direction d (unit, world space): the background and mirrors.
    Color radiance(const Vec3& d) const;
    /// radiance() of four directions at once (the background of a packet's misses), each bit
    /// for bit what radiance() gives it.
    void radiance4(const Vec3 d[4], Color out[4]) const;
    /// Irradiance/π around normal n: what a white Lambertian surface facing n reflects.
    Color diffuse(const Vec3& n) const;
    /// Radiance prefiltered by the GGX lobe of this roughness around the mirror direction r.
    Color specular(const Vec3& r, float roughness) const;

    /// Roughness levels prefiltered: 0, 1/(n−1), ..., 1 (level 0 is the radiance itself).
    static constexpr int kLevels = 6;

    /// What the filtering cost, in texels: the mip levels made, and the level the irradiance
    /// summed for each of its texels. Both follow the image's pixel count whatever its shape.
    size_t mipPixels() const;
    size_t irradianceSourcePixels() const { return irradianceSourcePixels_; }

private:
    Vec3 toMap(const Vec3& d) const;

    std::vector<EquirectImage> mips_;      ///< radiance, then halved copies (filtered lookups)
    OctahedralImage irradiance_;             ///< E/π
    std::vector<OctahedralImage> specular_;  ///< levels 1 .. kLevels − 1
    float cosRot_ = 1.f, sinRot_ = 0.f;
    size_t irradianceSourcePixels_ = 0;
};

class Scene;

/// Reads spec.file through fs (the built-in studio when it is empty) and prepares it. Throws
/// InputError naming the file for anything it cannot use.
std::shared_ptr<const EnvironmentLight> loadEnvironment(const EnvironmentSpec& spec, FileSource& fs);

/// Gives the scene its environment: the command line's if it names one, else the scene's own
/// (if any), with the command line's rotation and intensity applied to either. The environment
/// then also shows where rays miss everything.
void attachEnvironment(Scene& scene, const std::optional<EnvironmentSpec>& own, const SceneOptions& options, FileSource& fs);

}  // namespace rf
