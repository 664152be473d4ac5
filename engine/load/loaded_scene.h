#pragma once
/// What a loader hands back: the scene to render, and beside it what the file says about
/// time, which anim::Timeline interprets (the scene itself holds no timeline).
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "engine/scene/scene.h"

namespace rf {

/// A scene file's animation sections and the command line's choice of animation and camera.
/// Empty: the default timeline (a turntable for a bare model, each model's default animations
/// looped: anim::defaultAnimations).
struct TimelineSource {
    /// The scene file's animation sections as parsed JSON, null without any:
    /// {"timeline": {...}, "timeline_file": path if it came from its own file, "turntable": {...}}.
    /// Nothing parses or rewrites it as text again.
    std::shared_ptr<const nlohmann::json> sections;
    /// --animation NAME|INDEX (SceneOptions::animation): the animation every animated model
    /// plays, over the scene file's "animation".
    std::optional<std::string> animation;
    /// --camera N (SceneOptions::camera, or a scene file model's "camera"): the film looks
    /// through Scene::gltfCameras[N], following its node's animation; cameraSource names what
    /// chose it, for messages.
    std::optional<int> camera;
    std::string cameraSource = "--camera";
};

struct LoadedScene {
    Scene scene;
    TimelineSource timeline;
};

}  // namespace rf
