#include "engine/load/gltf/gltf_lights_cameras.h"

#include <cstdio>

#include "engine/util/errors.h"
#include "engine/lights/exposure.h"

namespace rf::gltf {

namespace {

/// A node axis in render space, unit length (the axis itself if the node collapses it).
Vec3 nodeAxis(const DMat4& renderFromNode, const glm::dvec3& a) {
    const glm::dvec3 v = glm::dmat3(renderFromNode) * a;
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? Vec3(v / len) : Vec3(a);
}

}  // namespace

void checkPunctualLight(const tinygltf::Light& gl, bool rangeGiven, const std::string& file, int index) {
    // As a scene file's lights are checked (json_scene_loader.cpp): a value out of range is
    // refused, never clamped into a light that shines black.
    const std::string where = "KHR_lights_punctual.lights[" + std::to_string(index) + "]" + (gl.name.empty() ? "" : " (\"" + gl.name + "\")");
    auto shown = [](double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", v);
        return std::string(text);
    };
    auto refuse = [&](const std::string& field, const std::string& value, const std::string& expected) {
        throw InputError(file, where + "." + field + " " + value + ": " + expected);
    };
    if (gl.color.size() == 3 && (gl.color[0] < 0.0 || gl.color[1] < 0.0 || gl.color[2] < 0.0))
        refuse("color", "[" + shown(gl.color[0]) + ", " + shown(gl.color[1]) + ", " + shown(gl.color[2]) + "]", "colour components must be ≥ 0");
    if (gl.intensity < 0.0) refuse("intensity", shown(gl.intensity), "expected a number ≥ 0");
    if (rangeGiven && !(gl.range > 0.0)) refuse("range", shown(gl.range), "expected a positive distance (leave range out for no limit)");
    if (gl.type == "spot") {
        if (gl.spot.innerConeAngle < 0.0) refuse("spot.innerConeAngle", shown(gl.spot.innerConeAngle), "expected radians ≥ 0");
        if (!(gl.spot.outerConeAngle > 0.0)) refuse("spot.outerConeAngle", shown(gl.spot.outerConeAngle), "expected radians > 0");
        if (gl.spot.innerConeAngle > gl.spot.outerConeAngle)
            refuse("spot.innerConeAngle", shown(gl.spot.innerConeAngle), "must not exceed outerConeAngle " + shown(gl.spot.outerConeAngle));
    }
}

Light punctualLight(const tinygltf::Light& gl, const DMat4& renderFromNode, const std::string& file, int index) {
    Light L;
    L.name = gl.name;
    L.position = Vec3(glm::dvec3(renderFromNode[3]));
    L.direction = nodeAxis(renderFromNode, glm::dvec3(0, 0, -1));
    if (gl.color.size() == 3) L.color = Color(float(gl.color[0]), float(gl.color[1]), float(gl.color[2]));
    // Photometric to radiometric at 683 lm/W: cd → W/sr (point, spot), lx → W/m² (directional).
    L.intensity = float(std::max(0.0, std::isfinite(gl.intensity) ? gl.intensity : 1.0) / double(kLumensPerWatt));
    L.photometric = true;
    L.range = gl.range > 0.0 && std::isfinite(gl.range) ? float(gl.range) : 0.f;
    if (gl.type == "directional") {
        L.type = LightType::Directional;
    } else {
        L.type = gl.type == "spot" ? LightType::Spot : LightType::Point;
        L.attenuation = Vec3(0.f, 0.f, 1.f);  // inverse square, as glTF specifies
        if (L.type == LightType::Spot) {
            L.innerCone = float(std::clamp(gl.spot.innerConeAngle, 0.0, double(kPi) / 2));
            L.outerCone = float(std::clamp(gl.spot.outerConeAngle, double(L.innerCone), double(kPi) / 2));
        }
    }
    if (!isFinite(L.color) || !isFinite(L.position) || !std::isfinite(L.intensity))
        throw InputError(file, "lights[" + std::to_string(index) + "]: non-finite values");
    return L;
}

std::optional<Camera> gltfCamera(const tinygltf::Camera& gc, const DMat4& renderFromNode, std::string& why, std::string& fault) {
    Camera c = cameraOnNode(Camera{}, renderFromNode);
    fault.clear();
    c.fovHorizontal = false;
    if (gc.type == "perspective") {
        const double fov = glm::degrees(gc.perspective.yfov);
        if (!(fov > 0.0 && fov < 180.0)) {
            char v[32];
            std::snprintf(v, sizeof v, "%g", gc.perspective.yfov);
            fault = std::string("perspective.yfov ") + v + " is not a field of view (expected radians between 0 and pi)";
        }
        c.fovDeg = float(fault.empty() ? fov : 45.0);  // never shown: useGltfCamera refuses it
        return c;
    }
    if (gc.type != "orthographic") {
        why = "type \"" + gc.type + "\" is neither perspective nor orthographic";
        return std::nullopt;
    }
    // The specification forbids 0 and advises against negative magnifications; a sign would
    // only mirror the image, so the magnitude is taken.
    auto usable = [](double m) { return std::isfinite(m) && std::abs(m) > 0.0 && std::abs(m) < 1e30; };
    c.orthographic = true;
    if (usable(gc.orthographic.ymag)) {
        c.orthoHalf = float(std::abs(gc.orthographic.ymag));
    } else if (usable(gc.orthographic.xmag)) {
        c.orthoHalf = float(std::abs(gc.orthographic.xmag));
        c.fovHorizontal = true;
    } else {
        why = "orthographic camera without a usable xmag or ymag";
        return std::nullopt;
    }
    return c;
}

}  // namespace rf::gltf
