#pragma once
/// KHR_lights_punctual lights and glTF perspective cameras, placed by their node's transform.
#include <optional>
#include <string>

#include <tiny_gltf.h>

#include "camera.h"
#include "light.h"
#include "vec_math.h"

namespace rf::gltf {

/// Engine light for a glTF punctual light on a node. Intensity mapping: point and spot lights
/// (candela) become intensity/π with inverse-square attenuation, so a Lambertian surface of
/// albedo ρ at distance d facing the light shows ρ·cd/d² as the physical radiance·π would;
/// directional lights (lux) become lux/π. Throws InputError(file, …) on non-finite values.
Light punctualLight(const tinygltf::Light& light, const DMat4& renderFromNode, const std::string& file, int index);

/// Engine camera for a glTF perspective camera on a node (looking down the node's −z with +y
/// up); nullopt for orthographic cameras, which the pin-hole camera cannot show. A yfov that is
/// no field of view (0, negative, π or more, not a number) leaves `fault` saying so (else "").
std::optional<Camera> perspectiveCamera(const tinygltf::Camera& camera, const DMat4& renderFromNode, std::string& fault);

}  // namespace rf::gltf
