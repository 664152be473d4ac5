#pragma once
/// KHR_lights_punctual lights and glTF perspective and orthographic cameras, placed by their
/// node's transform.
#include <optional>
#include <string>

#include <tiny_gltf.h>

#include "engine/geometry/camera.h"
#include "engine/lights/light.h"
#include "engine/util/vec_math.h"

namespace rf::gltf {

/// Engine light for a glTF punctual light on a node. Intensity mapping: point and spot lights
/// (candela) become intensity/π with inverse-square attenuation, so a Lambertian surface of
/// albedo ρ at distance d facing the light shows ρ·cd/d² as the physical radiance·π would;
/// directional lights (lux) become lux/π. Throws InputError(file, …) on non-finite values.
/// Throws InputError(file, "KHR_lights_punctual.lights[N] (\"NAME\").FIELD VALUE: expected ...")
/// for a value a scene file would refuse too: a negative colour component or intensity, a range
/// given as 0 or less (rangeGiven: the file has the key; tinygltf reads a missing range as 0), a
/// negative or zero cone angle, an inner cone angle past the outer one.
void checkPunctualLight(const tinygltf::Light& light, bool rangeGiven, const std::string& file, int index);

Light punctualLight(const tinygltf::Light& light, const DMat4& renderFromNode, const std::string& file, int index);

/// Engine camera for a glTF camera on a node, looking down the node's −z with +y up (the node's
/// scale does not enter). Perspective: yfov, the image's aspect in place of aspectRatio (as
/// the specification asks of a viewport). Orthographic: ymag is the view's half height and the
/// width follows the image's aspect (xmag when that aspect is xmag/ymag), so pixels stay
/// square; without a usable ymag, xmag gives the half width. znear and zfar are not used.
/// nullopt (why says why) for an unknown type or an orthographic camera without a magnification.
/// A perspective yfov that is no field of view (0, negative, π or more, not a number) leaves
/// `fault` saying so (else ""): the camera is kept and refused only when used.
std::optional<Camera> gltfCamera(const tinygltf::Camera& camera, const DMat4& renderFromNode, std::string& why, std::string& fault);

}  // namespace rf::gltf
