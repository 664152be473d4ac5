#pragma once
/// Bounding boxes of the scene's bounded primitives, as its trees are built over them.
#include "engine/geometry/aabb.h"
#include "engine/geometry/shapes.h"

namespace rf {

inline Aabb triangleBox(const Vec3& a, const Vec3& b, const Vec3& c) {
    Aabb box;
    box.grow(a);
    box.grow(b);
    box.grow(c);
    return box;
}

inline Aabb sphereBox(const Sphere& s) {
    Aabb box;
    box.lo = s.center - Vec3(s.radius);
    box.hi = s.center + Vec3(s.radius);
    return box;
}

}  // namespace rf
