#pragma once
// A small turntable scene for the farm tests, loaded from memory as the workers load theirs.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "engine/util/file_source.h"
#include "farm/cluster/render_engine.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::testing {

/// Floor, mirror sphere, red sphere, one point light; a 6-frame turntable.
inline const char* kFarmSceneJson = R"({
  "camera": { "eye": [0, 2, -6], "target": [0, 0.8, 0], "up": [0, 1, 0], "fov": 50 },
  "background": [0.1, 0.1, 0.2],
  "render": { "width": 40, "height": 30, "spp": 1, "max_depth": 3 },
  "materials": {
    "floor":  { "color": [0.9, 0.9, 0.9], "checker": { "color2": [0.2, 0.2, 0.2], "scale": 1 }, "diffuse": 0.8 },
    "red":    { "color": [0.8, 0.2, 0.1], "diffuse": 0.8, "specular": 0.5, "shininess": 30 },
    "mirror": { "color": [0.9, 0.9, 0.9], "diffuse": 0.1, "reflection": 0.8 }
  },
  "lights": [ { "type": "point", "position": [4, 6, -4], "color": [1, 1, 1] } ],
  "objects": [
    { "type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "floor" },
    { "type": "sphere", "center": [0, 0.8, 0], "radius": 0.8, "material": "mirror" },
    { "type": "sphere", "center": [1.6, 0.5, 0.4], "radius": 0.5, "material": "red" }
  ],
  "turntable": { "seconds": 1, "fps": 6 }
})";

inline FileBundle farmSceneBundle() {
    FileBundle b;
    b.files["farm_test.json"] = kFarmSceneJson;
    return b;
}

inline LoadedScene loadFarmScene() {
    BundleFileSource fs(farmSceneBundle());
    return loadScene("farm_test.json", fs);
}

// The reference: each frame rendered whole, on one thread, by the function every mode reduces to.
inline std::map<int, std::vector<uint8_t>> referenceFarmFrames() {
    LoadedScene sceneLoaded = loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    const RenderSettings s = scene.settings;
    std::map<int, std::vector<uint8_t>> out;
    int applied = -1;
    for (int f = tl.frameCount() - 1; f >= 0; --f)  // backwards: order must not matter
        out[f] = farm::RenderEngine::render(scene, tl, s, 1, {f, {0, 0, s.width, s.height}}, applied).rgb;
    return out;
}

}  // namespace rf::testing
