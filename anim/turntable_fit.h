#pragma once
/// Framing a turntable on what the camera sees of the model over the whole orbit, not on its
/// bounding sphere: the distance (and the height of the look-at point) at which the model's
/// projected silhouette fills the frame in the frame where it is largest and leaves it in none.
#include <functional>
#include <vector>

#include "engine/scene/scene.h"

namespace rf::anim {

/// Where the orbiting camera sits at one yaw: the unit vector from the orbit centre to the eye,
/// and the up vector given to lookAt (world +Y, or at a pole a horizontal one that turns with
/// the yaw, so the basis stays orthonormal).
struct OrbitPose {
    DVec3 toEye{0.0, 0.0, 1.0};
    DVec3 up{0.0, 1.0, 0.0};
};
/// yaw 0 puts the camera on +Z of the centre; elevation in radians above the horizontal plane.
OrbitPose orbitPose(double yaw, double elevation);

/// Points, relative to `center`, whose convex hull holds every mesh vertex and every sphere of
/// the scene, few enough to project for every frame of a film (at most 8 320 however many
/// triangles). The vertices are binned in 64 height slices × 64 sectors around the vertical
/// axis through center; each bin stands for a prism over its sector that holds its vertices,
/// and the points are those prisms' corners (a corner shared by two sectors takes the larger of
/// their radii and both height ranges). So the hull only grows: a sector edge sits 0.12 %
/// further out than the farthest vertex, and a bin's height range reaches across its sectors.
/// staticOnly: leave out the meshes that move (node ≥ 0), whose points come per frame instead.
std::vector<DVec3> silhouettePoints(const Scene& scene, const DVec3& center, bool staticOnly = false);

/// The eight corners of b, relative to center: for geometry that moves during the film, where
/// the box it sweeps is all that is known.
std::vector<DVec3> boxCorners(const Aabb& b, const DVec3& center);

/// What the camera of each frame sees: the yaws of the frames, the elevation, and the tangents
/// of half the field of view across and up.
struct OrbitView {
    std::vector<double> yaws;
    double elevation = 0.0;
    double tanX = 1.0, tanY = 1.0;
    /// Optional: points (relative to the orbit centre) that only frame f's camera must fit,
    /// e.g. where that frame poses the moving meshes; framePoints(f, emit) calls emit for each.
    std::function<void(size_t frame, const std::function<void(const DVec3&)>& emit)> framePoints;
};

struct OrbitFit {
    double distance = 0.0;  ///< from the look-at point to the eye
    double lift = 0.0;      ///< height of the look-at point above the orbit centre
};

/// The smallest distance at which every point (relative to the orbit centre) lies within
/// `fill` of the image's half-width and half-height in every frame, with the look-at point
/// raised by the lift that centres the highest and lowest extents across all frames (kept
/// within ±maxLift). Exact for the points given: the fit is linear in the distance and the lift
/// once each point's camera coordinates at unit distance are known, so one pass over points ×
/// frames finds it. Distance 0 when there is nothing to fit.
OrbitFit fitOrbit(const std::vector<DVec3>& points, const OrbitView& view, double fill, double maxLift);

}  // namespace rf::anim
