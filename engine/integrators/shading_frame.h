#pragma once
/// The shading frame at a surface point: which side the viewer sees, the geometric normal and
/// the shading normal (interpolated, then normal-mapped) turned to that side.
#include "engine/util/vec_math.h"

namespace rf {

class Scene;
struct SurfaceInteraction;

struct ShadingFrame {
    Vec3 ng{0.f};      ///< geometric normal, on the viewer's side
    Vec3 ns{0.f};      ///< shading normal, on the viewer's side (ng where it would face away)
    float side = 1.f;  ///< +1 seen from the front of the surface as it is defined, −1 from behind
    /// KHR_materials_clearcoat's normal: the interpolated normal bent by the coat's own normal
    /// texture (not the base's), on the viewer's side; ns where the material has no coat.
    Vec3 nc{0.f};
};

/// The frame at si seen from direction V (unit, from the point towards the viewer). A surface
/// seen from behind is lit on the side the viewer sees; a normal map bends ns within the
/// tangent frame; an interpolated normal turned away from the viewer falls back on ng, which
/// would otherwise draw a black contour on a visible face.
ShadingFrame shadingFrame(const Scene& scene, const SurfaceInteraction& si, const Vec3& V);

}  // namespace rf
