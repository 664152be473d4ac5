#pragma once
/// What primary rays that miss show, when a command overrides the scene's own background
/// (rayfarm's --background COLOR|transparent, for still, render, view and report).
#include <cstdint>

#include "engine/scene/scene.h"

namespace rf {

/// Trivially copyable: it travels to the workers inside the job broadcast.
struct BackgroundChoice {
    enum Kind : int32_t { FromScene = 0, Colour = 1, Transparent = 2 };
    Kind kind = FromScene;
    float r = 0.f, g = 0.f, b = 0.f;  ///< linear, as the scene file's "background"
};

/// Overrides the scene's background (nothing for FromScene).
void applyBackground(const BackgroundChoice& c, Scene& scene);

}  // namespace rf
