#include "turntable.h"

#include <cmath>

#include "frame_time.h"

namespace rf::anim {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;

/// Rotation by yaw about the vertical axis through c.
DVec3 yawAbout(const DVec3& p, const DVec3& c, double yaw) {
    const double s = std::sin(yaw), co = std::cos(yaw);
    const DVec3 r = p - c;
    return c + DVec3(co * r.x + s * r.z, r.y, -s * r.x + co * r.z);
}
}  // namespace

Turntable Turntable::framed(const TurntableSettings& s, const Scene& scene, const Aabb& b) {
    Turntable t;
    t.fps_ = s.fps;
    t.frames_ = anim::frameCount(s.seconds, s.fps);
    t.elevation_ = glm::radians(s.elevationDeg);
    t.startYaw_ = glm::radians(s.startYawDeg);
    t.lightsFollow_ = s.lightsFollow;
    if (s.fovDeg) t.fov_ = static_cast<float>(*s.fovDeg);

    const DVec3 camTarget(scene.camera.target), camEye(scene.camera.eye);
    double radius;
    if (!b.empty()) {
        t.center_ = DVec3(b.center());
        radius = 0.5 * glm::length(DVec3(b.extent()));
    } else {
        t.center_ = camTarget;
        radius = 0.0;
    }
    if (s.center) t.center_ = *s.center - scene.renderOrigin;
    if (s.distance > 0.0) {
        t.distance_ = s.distance;
    } else if (radius > 0.0) {
        // Fit the bounding sphere into the narrower of the two view angles, with a 10 % margin.
        const double fov = glm::radians(double(t.fov_.value_or(scene.camera.fovDeg)));
        const double aspect = double(scene.settings.width) / double(std::max(1, scene.settings.height));
        double tanX, tanY;
        if (scene.camera.fovHorizontal) {
            tanX = std::tan(0.5 * fov);
            tanY = tanX / aspect;
        } else {
            tanY = std::tan(0.5 * fov);
            tanX = tanY * aspect;
        }
        const double halfMin = std::atan(std::min(tanX, tanY));
        t.distance_ = 1.1 * radius / std::sin(halfMin);
    } else {
        const double d = glm::length(camEye - camTarget);
        t.distance_ = d > 0.0 ? d : 1.0;
    }
    return t;
}

double Turntable::yawAtFrame(int frame) const { return kTwoPi * double(frame) / double(frames_); }

double Turntable::yawAt(double t) const { return kTwoPi * (t * fps_) / double(frames_); }

void Turntable::apply(Scene& scene, double t, const std::vector<Light>& restLights) const {
    const double yaw = yawAt(t) + startYaw_;
    const double ce = std::cos(elevation_), se = std::sin(elevation_);
    const DVec3 horizontal(std::sin(yaw), 0.0, std::cos(yaw));
    const DVec3 eye = center_ + distance_ * (ce * horizontal + DVec3(0.0, se, 0.0));
    scene.camera.eye = Vec3(eye);
    scene.camera.target = Vec3(center_);
    // At a pole the view is parallel to the world up; screen-up then points away from the camera
    // horizontally, which keeps the basis orthonormal and still turning with the yaw.
    scene.camera.up = std::abs(ce) < 1e-6 ? Vec3(-std::copysign(1.0, se) * horizontal) : Vec3(0.f, 1.f, 0.f);
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
