#pragma once
/// What the command line adds to a scene as it loads, the same on every rank.
#include <optional>
#include <string>

namespace rf {

/// An environment light: a file, or the built-in studio when file is empty.
struct EnvironmentSpec {
    std::string file;
    float rotationDeg = 0.f;  ///< about +Y
    float intensity = 1.f;
};

struct SceneOptions {
    std::optional<EnvironmentSpec> environment;  ///< replaces the scene's own
    std::optional<float> environmentRotation;    ///< overrides the rotation of whichever is used
    std::optional<float> environmentIntensity;   ///< overrides its intensity
};

}  // namespace rf
