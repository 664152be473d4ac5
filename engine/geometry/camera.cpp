#include "engine/geometry/camera.h"

#include <cmath>

namespace rf {

namespace {

/// A node axis in render space, unit length (the axis itself if the node collapses it).
Vec3 nodeAxis(const DMat4& renderFromNode, const DVec3& a) {
    const DVec3 v = glm::dmat3(renderFromNode) * a;
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? Vec3(v / len) : Vec3(a);
}

}  // namespace

Camera cameraOnNode(Camera c, const DMat4& renderFromNode) {
    c.eye = Vec3(DVec3(renderFromNode[3]));
    c.target = c.eye + nodeAxis(renderFromNode, DVec3(0, 0, -1));
    c.up = nodeAxis(renderFromNode, DVec3(0, 1, 0));
    return c;
}

CameraBasis lookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
    CameraBasis b;
    const glm::dvec3 f = glm::dvec3(target) - glm::dvec3(eye);
    const double fl = glm::length(f);
    glm::dvec3 fwd = (fl > 0.0 && std::isfinite(fl)) ? f / fl : glm::dvec3(0, 0, -1);
    glm::dvec3 u = glm::dvec3(up);
    glm::dvec3 r = glm::cross(fwd, u);
    double rl = glm::length(r);
    if (!(rl > 1e-9 * std::max(1.0, glm::length(u)))) {
        // Forward parallel to up (or up is zero): take the world axis least aligned with forward.
        const glm::dvec3 a = glm::abs(fwd);
        u = (a.x <= a.y && a.x <= a.z) ? glm::dvec3(1, 0, 0) : (a.y <= a.z ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1));
        r = glm::cross(fwd, u);
        rl = glm::length(r);
    }
    r /= rl;
    const glm::dvec3 tu = glm::cross(r, fwd);
    b.right = Vec3(r);
    b.up = Vec3(tu);
    b.forward = Vec3(fwd);
    return b;
}

CameraRays::CameraRays(const Camera& cam, int w, int h) : origin(cam.eye), width(w), height(h) {
    basis = lookAt(cam.eye, cam.target, cam.up);
    const float aspect = static_cast<float>(w) / static_cast<float>(h);
    twoOverW = 2.f / static_cast<float>(w);
    twoOverH = 2.f / static_cast<float>(h);
    if (cam.orthographic) {
        // Like the field of view: the given axis spans ±orthoHalf, the other follows the aspect.
        orthographic = true;
        const float half = std::isfinite(cam.orthoHalf) && cam.orthoHalf > 0.f ? cam.orthoHalf : 1.f;
        tanHalfX = cam.fovHorizontal ? half : half * aspect;
        tanHalfY = cam.fovHorizontal ? half / aspect : half;
        if (cam.leftHanded) tanHalfX = -tanHalfX;
        pixelWidth = 2.f * tanHalfY / static_cast<float>(h);
        return;
    }
    const float half = 0.5f * glm::radians(std::clamp(cam.fovDeg, 1e-4f, 179.9f));
    if (cam.fovHorizontal) {
        tanHalfX = std::tan(half);
        tanHalfY = tanHalfX / aspect;
    } else {
        tanHalfY = std::tan(half);
        tanHalfX = tanHalfY * aspect;
    }
    if (cam.leftHanded) tanHalfX = -tanHalfX;  // mirror the image's x axis
    pixelSpread = 2.f * std::abs(tanHalfY) / static_cast<float>(h);
}

Ray CameraRays::generate(float x, float y) const {
    const float sx = (x * twoOverW - 1.f) * tanHalfX;
    const float sy = (1.f - y * twoOverH) * tanHalfY;
    Ray r;
    if (orthographic) {
        // Every ray leaves the image plane through the eye along the view direction; its cone is
        // a pixel wide and does not widen.
        r.o = origin + sx * basis.right + sy * basis.up;
        r.d = basis.forward;
        r.coneWidth = pixelWidth;
        return r;
    }
    r.o = origin;
    r.d = glm::normalize(basis.forward + sx * basis.right + sy * basis.up);
    r.coneSpread = pixelSpread;
    return r;
}

}  // namespace rf
