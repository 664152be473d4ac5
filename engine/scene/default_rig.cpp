#include "engine/scene/default_rig.h"

namespace rf {

Camera frameBoundingSphere(const Vec3& center, float radius, float aspect, float fovDeg, float margin) {
    Camera cam;
    cam.fovDeg = fovDeg;
    cam.fovHorizontal = false;
    const double halfV = glm::radians(double(fovDeg)) / 2.0;
    const double halfH = std::atan(std::tan(halfV) * (aspect > 0.f ? aspect : 1.f));
    const double half = std::min(halfV, halfH);
    const double r = radius > 0.f && std::isfinite(radius) ? radius : 1.0;
    const double dist = r * margin / std::sin(half);
    const double az = glm::radians(30.0), el = glm::radians(20.0);
    const glm::dvec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    cam.target = center;
    cam.eye = Vec3(glm::dvec3(center) + dist * dir);
    cam.up = Vec3(0.f, 1.f, 0.f);
    return cam;
}

void addDefaultLightRig(Scene& scene, const Camera& camera) {
    const CameraBasis b = lookAt(camera.eye, camera.target, camera.up);
    auto dir = [&](float right, float up, float toward) {
        // Direction the light travels: from its position (right, up, toward the viewer) to the model.
        return -glm::normalize(right * b.right + up * b.up - toward * b.forward);
    };
    Light key;
    key.name = "default key";
    key.type = LightType::Directional;
    key.direction = dir(-0.6f, 0.8f, 0.7f);
    key.intensity = 0.9f;
    key.castShadows = true;
    Light fill = key;
    fill.name = "default fill";
    fill.direction = dir(0.9f, 0.1f, 0.5f);
    fill.intensity = 0.3f;
    fill.castShadows = false;
    Light rim = key;
    rim.name = "default rim";
    rim.direction = dir(0.2f, 0.6f, -1.0f);
    rim.intensity = 0.5f;
    rim.castShadows = false;
    scene.lights.push_back(key);
    scene.lights.push_back(fill);
    scene.lights.push_back(rim);
}

void addDefaultKeyLight(Scene& scene, const Camera& camera) {
    Scene rig;
    addDefaultLightRig(rig, camera);
    Light key = rig.lights.front();
    key.intensity = 3.f;
    scene.lights.push_back(key);
}

}  // namespace rf
