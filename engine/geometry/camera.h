#pragma once
/// Perspective pin-hole and orthographic cameras, and their primary rays.
#include "engine/geometry/ray.h"

namespace rf {

struct Camera {
    Vec3 eye{0.f, 0.f, 5.f};
    Vec3 target{0.f};
    Vec3 up{0.f, 1.f, 0.f};
    float fovDeg = 45.f;         ///< full field of view along fovHorizontal ? x : y
    bool fovHorizontal = false;
    /// POV-Ray's convention: image x runs along up × forward, not forward × up. Lets a scene
    /// keep a left-handed modeller's coordinates and still render unmirrored.
    bool leftHanded = false;
    /// Orthographic: parallel rays along the view direction from a plane through the eye. The
    /// view spans ±orthoHalf scene units along the fov axis (vertical unless fovHorizontal), the
    /// other axis following the image's aspect, so pixels stay square; fovDeg is not used.
    bool orthographic = false;
    float orthoHalf = 1.f;
};

/// `lens` placed on a glTF node: looking down the node's −z with its +y up (the node's scale
/// does not enter; an axis the node collapses stays the unscaled one).
Camera cameraOnNode(Camera lens, const DMat4& renderFromNode);

/// World-from-camera basis: right, up and forward, orthonormal and right-handed.
struct CameraBasis {
    Vec3 right{1.f, 0.f, 0.f};
    Vec3 up{0.f, 1.f, 0.f};
    Vec3 forward{0.f, 0.f, -1.f};
};

/// Look-at that stays orthonormal when forward is parallel to up (another up is chosen) and
/// when eye == target (forward falls back to −z). Never NaN for finite input.
CameraBasis lookAt(const Vec3& eye, const Vec3& target, const Vec3& up);

/// Everything needed to shoot primary rays for one image size.
struct CameraRays {
    Vec3 origin;
    CameraBasis basis;
    /// Perspective: tangents of the half view angles; orthographic: the view's half width and
    /// height in scene units. tanHalfX < 0 for a left-handed camera.
    float tanHalfX = 1.f, tanHalfY = 1.f;
    bool orthographic = false;
    int width = 1, height = 1;
    float twoOverW = 2.f, twoOverH = 2.f;   ///< pixel to [0, 2] scale, so rays need no division
    float pixelSpread = 0.f;  ///< a pixel's angle at the image centre: each ray's Ray::coneSpread
    float pixelWidth = 0.f;   ///< orthographic: a pixel's width in scene units, each ray's Ray::coneWidth

    CameraRays(const Camera& cam, int width, int height);
    /// Ray through image position (x, y) in pixels, (0, 0) the top-left corner, with a cone one
    /// pixel wide.
    Ray generate(float x, float y) const;
};

}  // namespace rf
