#pragma once
/// --background COLOR|transparent, for still and render: what primary rays that miss show.
#include <cstdint>
#include <string>

#include "scene.h"

namespace rf::cli {

/// Trivially copyable: it travels to the workers inside the job broadcast.
struct BackgroundChoice {
    enum Kind : int32_t { FromScene = 0, Colour = 1, Transparent = 2 };
    Kind kind = FromScene;
    float r = 0.f, g = 0.f, b = 0.f;  ///< linear, as the scene file's "background"
};

/// "transparent", "#RRGGBB" (sRGB, as on a web page) or "R,G,B" (linear, as in a scene file).
/// Throws UsageError naming --background.
BackgroundChoice parseBackground(const std::string& text);

/// Overrides the scene's background (nothing for FromScene).
void applyBackground(const BackgroundChoice& c, Scene& scene);

}  // namespace rf::cli
