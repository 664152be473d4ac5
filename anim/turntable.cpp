#include "anim/turntable.h"

#include <cmath>

#include "anim/frame_time.h"
#include "anim/turntable_fit.h"

namespace rf::anim {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;

/// Rotation by yaw about the vertical axis through c.
DVec3 yawAbout(const DVec3& p, const DVec3& c, double yaw) {
    const double s = std::sin(yaw), co = std::cos(yaw);
    const DVec3 r = p - c;
    return c + DVec3(co * r.x + s * r.z, r.y, -s * r.x + co * r.z);
}

/// Tangents of half the view angle across and up for the camera's field of view and the
/// render settings' aspect ratio.
void viewTangents(const Scene& scene, double fovDeg, double& tanX, double& tanY) {
    const double fov = glm::radians(fovDeg);
    const double aspect = double(scene.settings.width) / double(std::max(1, scene.settings.height));
    if (scene.camera.fovHorizontal) {
        tanX = std::tan(0.5 * fov);
        tanY = tanX / aspect;
    } else {
        tanY = std::tan(0.5 * fov);
        tanX = tanY * aspect;
    }
}

/// Yaws of the film's frames (a dense, even sample of the loop for very long films).
std::vector<double> frameYaws(int frames, double startYaw) {
    constexpr int kMaxYaws = 1024;  // 0.35° apart: the silhouette moves by less than a vertex bin
    const int n = std::min(frames, kMaxYaws);
    std::vector<double> yaws(size_t(std::max(1, n)));
    for (int i = 0; i < int(yaws.size()); ++i) yaws[size_t(i)] = startYaw + kTwoPi * double(i) / double(yaws.size());
    return yaws;
}

}  // namespace

Turntable Turntable::framed(const TurntableSettings& s, const Scene& scene, const Aabb& b, bool geometryMoves,
                            const PosedPoints* posed) {
    Turntable t;
    t.fps_ = s.fps;
    t.frames_ = anim::frameCount(s.seconds, s.fps);
    t.elevation_ = glm::radians(s.elevationDeg);
    t.startYaw_ = glm::radians(s.startYawDeg);
    t.lightsFollow_ = s.lightsFollow;
    if (s.fovDeg) t.fov_ = static_cast<float>(*s.fovDeg);

    const DVec3 camTarget(scene.camera.target), camEye(scene.camera.eye);
    const double radius = b.empty() ? 0.0 : 0.5 * glm::length(DVec3(b.extent()));
    t.center_ = b.empty() ? camTarget : DVec3(b.center());
    if (s.center) t.center_ = *s.center - scene.renderOrigin;
    double tanX, tanY;
    viewTangents(scene, double(t.fov_.value_or(scene.camera.fovDeg)), tanX, tanY);
    if (s.distance > 0.0) {
        t.distance_ = s.distance;
    } else if (radius > 0.0 && s.fitSilhouette && t.fitToSilhouette(s, scene, b, geometryMoves, tanX, tanY, posed)) {
        // distance and look-at height set from the model's projection
    } else if (radius > 0.0) {
        // Fit the bounding sphere into the narrower of the two view angles, with a 10 % margin.
        t.distance_ = 1.1 * radius / std::sin(std::atan(std::min(tanX, tanY)));
    } else {
        const double d = glm::length(camEye - camTarget);
        t.distance_ = d > 0.0 ? d : 1.0;
    }
    return t;
}

bool Turntable::fitToSilhouette(const TurntableSettings& s, const Scene& scene, const Aabb& b, bool geometryMoves,
                              double tanX, double tanY, const PosedPoints* posed) {
    const bool perFrame = geometryMoves && posed && *posed;
    // Moving meshes: each frame's pose for that frame's camera when known, else the box they sweep.
    const std::vector<DVec3> pts = perFrame ? silhouettePoints(scene, center_, true)
                                   : geometryMoves ? boxCorners(b, center_) : silhouettePoints(scene, center_);
    OrbitView view;
    view.yaws = frameYaws(frames_, startYaw_);
    if (perFrame) {
        const DVec3 c = center_;
        view.framePoints = [posed, c](size_t f, const std::function<void(const DVec3&)>& emit) {
            (*posed)(int(f), [&](const DVec3& p) { emit(p - c); });
        };
    }
    view.elevation = elevation_;
    view.tanX = tanX;
    view.tanY = tanY;
    // A centre the user gave stays where it is; otherwise the look-at point may rise or sink
    // within the bounds to centre the model in the picture.
    const double maxLift = s.center ? 0.0 : 0.5 * double(b.extent().y);
    const OrbitFit fit = fitOrbit(pts, view, s.fill, maxLift);
    if (!(fit.distance > 0.0)) return false;
    distance_ = fit.distance;
    center_.y += fit.lift;
    return true;
}

double Turntable::yawAtFrame(int frame) const { return kTwoPi * double(frame) / double(frames_); }

double Turntable::yawAt(double t) const { return kTwoPi * (t * fps_) / double(frames_); }

void Turntable::apply(Scene& scene, double t, const std::vector<Light>& restLights) const {
    const OrbitPose pose = orbitPose(yawAt(t) + startYaw_, elevation_);
    scene.camera.eye = Vec3(center_ + distance_ * pose.toEye);
    scene.camera.target = Vec3(center_);
    scene.camera.up = Vec3(pose.up);
    if (fov_) scene.camera.fovDeg = *fov_;
    if (!lightsFollow_) return;
    const double turn = yawAt(t);  // lights keep their placement relative to frame 0's camera
    for (size_t i = 0; i < scene.lights.size() && i < restLights.size(); ++i) {
        const Light& r = restLights[i];
        Light& l = scene.lights[i];
        l.position = Vec3(yawAbout(DVec3(r.position), center_, turn));
        l.direction = Vec3(yawAbout(DVec3(r.direction), DVec3(0.0), turn));
    }
}

}  // namespace rf::anim
