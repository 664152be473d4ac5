#pragma once
/// What traversal finds (Hit) and what shading reads at that point (SurfaceInteraction), after
/// pbrt-v4's interaction.h.
#include <cstdint>

#include "engine/geometry/triangle.h"
#include "engine/util/vec_math.h"

namespace rf {

/// Closest hit found by traversal; resolved into a SurfaceInteraction only for shading.
struct Hit {
    float t = kInf;
    uint32_t prim = 0;  ///< triangles first, then spheres (SceneGeometry numbers them)
    TriangleHit tri;
    Vec3 sphereRel{0.f};
};

struct SurfaceInteraction {
    Vec3 p{0.f};       ///< hit point
    Vec3 pError{0.f};  ///< per-axis absolute error bound of p
    Vec3 ng{0.f};      ///< geometric normal (unit, as the surface defines it)
    Vec3 ns{0.f};      ///< shading normal (unit; interpolated, or ng)
    Vec2 uv{0.f};
    Vec2 uv1{0.f};
    Vec4 tangent{0.f};
    Vec4 color{1.f};   ///< vertex colour (glTF COLOR_0, linear RGBA); white without one
    /// The hit ray's cone (Ray::coneWidth, coneSpread) at p: the width there and its spread.
    float coneWidth = 0.f, coneSpread = 0.f;
    /// Texture-coordinate area the cone's footprint covers on the surface, for TEXCOORD_0 (x)
    /// and TEXCOORD_1 (y): what texture lookups filter over (mip level). 0: unfiltered.
    Vec2 uvArea{0.f};
    int material = 0;
    int mesh = -1;
    uint32_t tri = 0;
    uint32_t prim = ~0u;  ///< primitive id (Hit::prim)
    TriangleHit bary;
};

}  // namespace rf
