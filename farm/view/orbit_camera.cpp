#include "farm/view/orbit_camera.h"

#include <algorithm>
#include <cmath>

namespace rf::view {

namespace {
constexpr double kRadiansPerPixel = 0.008;
constexpr double kPoleMargin = 0.02;  // radians kept between the view and the up axis

DVec3 d3(const Vec3& v) { return DVec3(v.x, v.y, v.z); }
double verticalTanHalf(const Camera& c, double aspect) {
    const double t = std::tan(0.5 * c.fovDeg * 3.14159265358979323846 / 180.0);
    return c.fovHorizontal ? t / aspect : t;
}
}  // namespace

Camera orbit(const Camera& c, double dx, double dy) {
    const DVec3 target = d3(c.target);
    const DVec3 up = glm::normalize(d3(c.up));
    DVec3 off = d3(c.eye) - target;
    const double r = glm::length(off);
    if (!(r > 0.0)) return c;
    // Yaw about the up axis, pitch measured from it: spherical coordinates around the target.
    const double sign = c.leftHanded ? -1.0 : 1.0;
    const double pitch0 = std::acos(std::clamp(glm::dot(off / r, up), -1.0, 1.0));
    const double pitch = std::clamp(pitch0 - dy * kRadiansPerPixel, kPoleMargin, 3.14159265358979323846 - kPoleMargin);
    const double yaw = -dx * kRadiansPerPixel * sign;
    DVec3 horiz = off - up * glm::dot(off, up);
    if (glm::length(horiz) < 1e-12 * r) {  // on the pole: any horizontal direction will do
        horiz = std::abs(up.x) < 0.9 ? glm::cross(up, DVec3(1, 0, 0)) : glm::cross(up, DVec3(0, 1, 0));
    }
    horiz = glm::normalize(horiz);
    const DVec3 side = glm::cross(up, horiz);
    const DVec3 h = horiz * std::cos(yaw) + side * std::sin(yaw);
    Camera out = c;
    out.eye = Vec3(target + r * (up * std::cos(pitch) + h * std::sin(pitch)));
    return out;
}

Camera pan(const Camera& c, double dx, double dy, int imageHeight) {
    const CameraBasis b = lookAt(c.eye, c.target, c.up);
    const double dist = glm::length(d3(c.target) - d3(c.eye));
    // An orthographic view's height is the same at every distance: 2·orthoHalf (vertical axis).
    const double viewHeight = c.orthographic ? 2.0 * double(c.orthoHalf) : 2.0 * dist * verticalTanHalf(c, 1.0);
    const double perPixel = viewHeight / std::max(1, imageHeight);
    const double sign = c.leftHanded ? -1.0 : 1.0;
    const DVec3 move = d3(b.right) * (-dx * perPixel * sign) + d3(b.up) * (dy * perPixel);
    Camera out = c;
    out.eye = Vec3(d3(c.eye) + move);
    out.target = Vec3(d3(c.target) + move);
    return out;
}

Camera zoom(const Camera& c, double steps) {
    const DVec3 target = d3(c.target);
    const DVec3 off = d3(c.eye) - target;
    const double r = glm::length(off);
    if (!(r > 0.0)) return c;
    const double nr = std::max(r * std::pow(0.9, steps), 1e-6);
    Camera out = c;
    out.eye = Vec3(target + off * (nr / r));
    // Moving an orthographic eye changes nothing on screen: its view shrinks by as much instead.
    if (c.orthographic) out.orthoHalf = float(std::max(double(c.orthoHalf) * std::pow(0.9, steps), 1e-9));
    return out;
}

Camera frameBox(const Camera& c, const Aabb& box, double aspect) {
    const DVec3 lo = d3(box.lo), hi = d3(box.hi);
    if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return c;  // empty box: nothing to frame
    const DVec3 center = 0.5 * (lo + hi);
    const double radius = std::max(0.5 * glm::length(hi - lo), 1e-6);
    const double tanV = verticalTanHalf(c, aspect);
    const double tanNarrow = std::min(tanV, tanV * aspect);
    const double dist = 1.1 * radius * std::sqrt(1.0 + 1.0 / (tanNarrow * tanNarrow));
    DVec3 dir = d3(c.eye) - d3(c.target);
    dir = glm::length(dir) > 0.0 ? glm::normalize(dir) : DVec3(0, 0, 1);
    Camera out = c;
    out.target = Vec3(center);
    out.eye = Vec3(center + dir * dist);
    if (c.orthographic) {
        // The box's sphere across the narrower side of the view, with the same margin.
        if (c.fovHorizontal) out.orthoHalf = float(1.1 * radius * std::max(1.0, aspect));
        else out.orthoHalf = float(1.1 * radius * std::max(1.0, 1.0 / aspect));
    }
    return out;
}

}  // namespace rf::view
