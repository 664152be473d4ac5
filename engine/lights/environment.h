#pragma once
/// Environment light: an equirectangular radiance image around the scene, oriented as Blender
/// maps one on its world for an imported glTF (+Y up): direction d looks up
/// u = 0.5 + atan2(d.z, d.x)/2π, v = acos(d.y)/π, v = 0 the top row. So +X sees the image
/// centre, +Z the point three quarters across, +Y the top row.
#include <string>
#include <functional>
#include <vector>

#include "engine/util/simd4.h"
#include "engine/util/vec_math.h"

namespace rf {

/// Equirectangular float RGB radiance, row 0 at the top.
struct EquirectImage {
    int width = 0, height = 0;
    std::vector<Color> texels;

    const Color& at(int x, int y) const { return texels[size_t(y) * width + x]; }
    /// Bilinear at (u, v) in [0, 1]²: wraps in u, clamps in v.
    Color sample(Vec2 uv) const;
    /// sample() at four (u, v) lanes, each bit for bit what sample() gives it.
    void sample4(F4 u, F4 v, Color out[4]) const;
    /// Each 2×2 block averaged (odd sizes keep their last row/column): the next mip level.
    EquirectImage halved() const;
};

/// (u, v) of a unit world direction, and back.
Vec2 equirectUv(const Vec3& d);
Vec3 equirectDirection(Vec2 uv);
/// equirectUv of four directions (d[axis] lane by lane), each bit for bit equirectUv's; false
/// (u, v untouched) if a lane holds a NaN, which the caller then takes one by one.
bool equirectUv4(const F4 d[3], F4& u, F4& v);

/// The sphere on a square by the octahedral projection (Praun and Hoppe 2003; Engelhardt and
/// Dachsbacher 2008), +Y at the centre, −Y at the four corners: a direction's texel costs a sum
/// and a division, not the two arc tangents of an equirect. For the smooth prefiltered copies of
/// an environment, read several times at every shading point.
struct OctahedralImage {
    int size = 0;                ///< texels per side
    std::vector<Color> texels;   ///< (size + 2)², row-major: a one-texel border copied from across each fold

    /// Each texel centre's direction through f (rows spread over threads); then the border.
    static OctahedralImage build(int size, int threads, const std::function<Color(const Vec3&)>& f);
    /// Bilinear at direction d (any length but 0), seamless across the folds.
    Color sample(const Vec3& d) const;
};

/// (u, v) in [0, 1]² of direction d (any length but 0) on the octahedral square, and back (unit).
Vec2 octahedralUv(const Vec3& d);
Vec3 octahedralDirection(Vec2 uv);

/// Pixels an environment file may have: 8192 × 4096 (an "8K" HDRI) and no more.
constexpr long long kMaxEnvironmentPixels = 8192LL * 4096LL;
/// The most one side of an environment file may exceed the other by (an equirect is 2:1).
constexpr long long kMaxEnvironmentAspect = 8;

/// Decodes an equirectangular .hdr (Radiance RGBE, through stb) or .exr (OpenEXR: every
/// compression it reads, DWAA/DWAB included) from its bytes, told apart by their magic numbers.
/// Throws InputError(path, ...) for anything else, a malformed or truncated file, a size beyond
/// kMaxEnvironmentPixels or sides further apart than kMaxEnvironmentAspect, or non-finite
/// radiance. Negative values (lossy DWA ringing) become 0.
EquirectImage decodeEnvironment(const std::string& bytes, const std::string& path);

/// The built-in studio for bare models, made in code: a dim grey room with a warm floor
/// bounce, a broad soft top light and two soft boxes (key front-left, rim back-right).
EquirectImage builtinStudioEnvironment(int width = 256);

}  // namespace rf
