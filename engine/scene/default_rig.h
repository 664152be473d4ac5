#pragma once
/// Defaults for a model given alone: a camera framed on its bounding sphere, and a key/fill/rim
/// light rig for models that bring no lights.
#include "engine/geometry/camera.h"
#include "engine/lights/light.h"
#include "engine/scene/scene.h"

namespace rf {

/// Camera looking at `center` from the front-right and a little above (glTF: +Y up, models face
/// +Z), far enough that a sphere of `radius` fits the narrower field of view with `margin`.
Camera frameBoundingSphere(const Vec3& center, float radius, float aspect, float fovDeg = 40.f, float margin = 1.15f);

/// Adds three directional lights relative to the camera's view: a shadow-casting key from the
/// upper left, a weaker fill from the right, and a rim from behind. Directional lights keep the
/// look independent of the model's scale.
void addDefaultLightRig(Scene& scene, const Camera& camera);

/// The key light of addDefaultLightRig alone, at the glTF model's photometric scale (3 W/m²,
/// about a bright overcast day's sun): beside the built-in studio environment, which lights
/// everything else, it draws the crisp shadows.
void addDefaultKeyLight(Scene& scene, const Camera& camera);

}  // namespace rf
