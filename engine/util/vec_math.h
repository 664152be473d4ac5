#pragma once
/// Shared math vocabulary: GLM vectors, float error bounds and small helpers.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace rf {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using DVec3 = glm::dvec3;
using DMat4 = glm::dmat4;
using DQuat = glm::dquat;
using Color = glm::vec3;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kPi = 3.14159265358979323846f;
constexpr float kMachineEps = std::numeric_limits<float>::epsilon() * 0.5f;

/// pbrt's gamma(n): bound on the relative error of n chained float operations.
constexpr float gamma(int n) { return (n * kMachineEps) / (1 - n * kMachineEps); }

inline float maxComponent(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
/// |v| per component without a branch. glm::abs on a vector calls its scalar abs through a
/// function pointer, which GCC left out of line as three compares and jumps on the signs: on the
/// random signs of secondary rays' directions those jumps were mispredicted. std::fabs clears
/// the sign bit (andps). The only difference: -0 and NaN come out positive.
inline Vec3 absComponents(const Vec3& v) { return Vec3(std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)); }
inline float luminanceMax(const Color& c) { return maxComponent(c); }
inline bool isFinite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// The next float towards +inf (pbrt-v4's NextFloatUp: bit arithmetic, no libm call).
inline float nextFloatUp(float v) {
    if (std::isinf(v) && v > 0.f) return v;
    if (v == -0.f) v = 0.f;
    uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    u = (v >= 0.f) ? u + 1 : u - 1;
    std::memcpy(&v, &u, sizeof u);
    return v;
}
/// The next float towards −inf.
inline float nextFloatDown(float v) {
    if (std::isinf(v) && v < 0.f) return v;
    if (v == 0.f) v = -0.f;
    uint32_t u;
    std::memcpy(&u, &v, sizeof u);
    u = (v > 0.f) ? u - 1 : u + 1;
    std::memcpy(&v, &u, sizeof u);
    return v;
}

/// Orthonormal basis around a unit vector (Duff et al. 2017, branchless).
inline void orthonormalBasis(const Vec3& n, Vec3& t, Vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace rf
