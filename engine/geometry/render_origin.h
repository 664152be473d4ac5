#pragma once
/// Where render space starts: geometry is rebased by an origin near what the camera looks at,
/// so that float precision is spent where the picture is.
#include <glm/glm.hpp>

#include "engine/util/vec_math.h"

namespace rf {

/// The render-space origin for a scene whose camera looks at `target`: the target rounded to a
/// multiple of 64, so geometry near the camera's focus keeps float precision.
inline DVec3 chooseRenderOrigin(const DVec3& target) { return glm::round(target / 64.0) * 64.0; }

}  // namespace rf
