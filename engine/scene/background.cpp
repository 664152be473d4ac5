#include "engine/scene/background.h"

namespace rf {

void applyBackground(const BackgroundChoice& c, Scene& scene) {
    if (c.kind == BackgroundChoice::Transparent) {
        scene.transparentBackground = true;
        scene.exactBackground = false;
    } else if (c.kind == BackgroundChoice::Colour) {
        scene.transparentBackground = false;
        scene.exactBackground = true;  // shown exactly, not exposed (Scene::exactBackground)
        scene.background = Color(c.r, c.g, c.b);
        scene.environmentBackground = false;  // the environment still lights and is reflected
    }
}

}  // namespace rf
