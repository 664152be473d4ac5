#include "engine/scene/background.h"

namespace rf {

void applyBackground(const BackgroundChoice& c, Scene& scene) {
    if (c.kind == BackgroundChoice::Transparent) {
        scene.transparentBackground = true;
    } else if (c.kind == BackgroundChoice::Colour) {
        scene.transparentBackground = false;
        scene.background = Color(c.r, c.g, c.b);
        scene.environmentBackground = false;  // the environment still lights and is reflected
    }
}

}  // namespace rf
