#pragma once
/// The viewer's camera moves: orbit about the target, pan in the view plane, dolly towards the
/// target, frame a bounding box. Pure functions of the camera and the input, no window system.
#include "engine/geometry/aabb.h"
#include "engine/geometry/camera.h"

namespace rf::view {

/// Turns the eye about the target: dx pixels yaw about the camera's up, dy pixels pitch about
/// its right axis. The eye never crosses the pole, so the image never flips.
Camera orbit(const Camera& c, double dxPixels, double dyPixels);
/// Moves eye and target together so the point under the cursor follows it (imageHeight pixels
/// span the vertical field of view at the target's distance).
Camera pan(const Camera& c, double dxPixels, double dyPixels, int imageHeight);
/// Moves the eye towards the target (steps > 0) or away, 10 % of the distance per step.
Camera zoom(const Camera& c, double steps);
/// Keeps the view direction and puts the whole box in view, with a 10 % margin.
Camera frameBox(const Camera& c, const Aabb& box, double aspect);

}  // namespace rf::view
