#pragma once
/// The turntable preset: the camera orbits the scene's bounds once per loop, yaw built as
/// 2π·f/N from the frame so the loop closes without a duplicated frame (never a slerp between
/// 0° and 360° keys, which are the same rotation).
#include <functional>
#include <optional>
#include <vector>

#include "engine/scene/scene.h"

namespace rf::anim {

struct TurntableSettings {
    double seconds = 4.0;
    double fps = 30.0;
    double elevationDeg = 20.0;  ///< above the horizontal plane through the centre; ±90 = poles
    double distance = 0.0;       ///< from the centre; 0 = auto (see fitSilhouette)
    double startYawDeg = 0.0;    ///< yaw of frame 0; 0 puts the camera on +z looking towards −z
    bool lightsFollow = false;   ///< lights orbit with the camera (the object seems to turn)
    std::optional<DVec3> center; ///< world space; default: centre of the scene's bounds
    std::optional<double> fovDeg;
    /// Auto distance: false fits the bounds' sphere into the narrower view angle (scene files);
    /// true fits the model's projected silhouette over every frame of the orbit, and raises the
    /// look-at point to centre it when `center` is not given (a bare glTF's turntable).
    bool fitSilhouette = false;
    /// With fitSilhouette: the share of the image's half-width or half-height the model reaches
    /// in the frame where it is largest.
    double fill = 0.94;
};

class Turntable {
public:
    Turntable() = default;
    /// Frames the orbit on scene.geometry.bounds() (render space) with the scene camera's field of view
    /// and the render settings' aspect ratio. Falls back to the camera's target and distance
    /// when the scene has no bounded geometry.
    static Turntable framed(const TurntableSettings& s, const Scene& scene) {
        return framed(s, scene, scene.geometry.bounds());
    }
    /// The same, framed on the given bounds (render space), e.g. those an animation sweeps.
    /// geometryMoves: an animation moves meshes, so a silhouette fit uses the bounds' corners
    /// (the rest pose's vertices say nothing of the other frames).
    /// Points of frame f's pose of the moving meshes (render space), emitted one by one.
    using PosedPoints = std::function<void(int frame, const std::function<void(const DVec3&)>& emit)>;
    /// posed (with geometryMoves): where each frame poses the moving meshes, so each frame's
    /// camera fits that frame's pose rather than the box the whole film sweeps.
    static Turntable framed(const TurntableSettings& s, const Scene& scene, const Aabb& bounds, bool geometryMoves = false,
                            const PosedPoints* posed = nullptr);

    int frameCount() const { return frames_; }
    double fps() const { return fps_; }
    /// 2π·frame/N.
    double yawAtFrame(int frame) const;
    /// Yaw at time t: 2π·(t·fps)/N, so frame f (t = f/fps) gets 2π·f/N.
    double yawAt(double t) const;
    /// Camera (and, following, lights rotated from restLights) at time t. Absolute: depends on
    /// t and the rest state alone.
    void apply(Scene& scene, double t, const std::vector<Light>& restLights) const;

    /// The look-at point (render space): the orbit centre, raised by a silhouette fit's lift.
    DVec3 centerRender() const { return center_; }
    double distance() const { return distance_; }

private:
    /// Sets distance_ and lifts center_ from the silhouette fit; false when there is nothing to
    /// fit (the caller falls back to the bounding sphere).
    bool fitToSilhouette(const TurntableSettings& s, const Scene& scene, const Aabb& b, bool geometryMoves, double tanX,
                         double tanY, const PosedPoints* posed);

    int frames_ = 1;
    double fps_ = 30.0;
    double elevation_ = 0.0;  ///< radians
    double startYaw_ = 0.0;   ///< radians
    double distance_ = 1.0;
    DVec3 center_{0.0};       ///< render space
    bool lightsFollow_ = false;
    std::optional<float> fov_;
};

}  // namespace rf::anim
