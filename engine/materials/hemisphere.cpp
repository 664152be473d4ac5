#include "engine/materials/hemisphere.h"

#include <algorithm>
#include <cmath>

#include "engine/materials/brdf_gltf.h"

namespace rf {

Vec2 stratifiedPoint(uint32_t i, uint32_t n, Vec2 rotation) {
    Vec2 u = pbr::hammersley(i, n) + rotation;
    u -= glm::floor(u);
    return glm::min(u, Vec2(0x1.fffffep-1f));
}

Vec3 cosineHemisphere(Vec2 u) {
    // Concentric map of the square onto the unit disc, then lifted onto the hemisphere.
    const float a = 2.f * u.x - 1.f, b = 2.f * u.y - 1.f;
    if (a == 0.f && b == 0.f) return Vec3(0.f, 0.f, 1.f);
    float r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = (kPi / 4.f) * (b / a);
    } else {
        r = b;
        phi = (kPi / 2.f) - (kPi / 4.f) * (a / b);
    }
    const float x = r * std::cos(phi), y = r * std::sin(phi);
    return Vec3(x, y, std::sqrt(std::max(0.f, 1.f - x * x - y * y)));
}

}  // namespace rf
