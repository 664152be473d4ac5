#pragma once
/// What a parsed timeline holds: key tracks for the camera and lights, a turntable, and the
/// model animations to play. Internal to anim/ (Timeline keeps one, shared and immutable).
#include <optional>
#include <string>
#include <vector>

#include "anim/gltf_animation.h"
#include "anim/keyframes.h"
#include "anim/turntable.h"
#include "engine/load/loaded_scene.h"

namespace rf::anim {

/// POV-Ray style orbit: eye = center + (r·sin 2πc, height, −r·cos 2πc), c = phase + t/period.
struct Orbit {
    DVec3 center{0.0};  ///< world space
    double radius = 1.0;
    double height = 0.0;
    double period = 1.0;  ///< seconds per turn
    double phase = 0.0;   ///< turns at t = 0
};

struct CameraTracks {
    std::optional<KeyTrack> position, target, orientation, up, fov;
    std::optional<Orbit> orbit;
    bool any() const { return position || target || orientation || up || fov || orbit; }
};

struct LightTracks {
    int light = 0;
    std::optional<KeyTrack> position, direction, color, intensity, innerDeg, outerDeg;
};

/// The film looks through a camera of a glTF file (--camera N): Scene::gltfCameras[index],
/// on node `node` of model `model`, posed each frame by that model's player (or at rest).
struct FileCamera {
    int index = 0;
    int model = -1, node = -1;
    int source = -1;              ///< the file's cameras[] entry (its animation pointers' index)
    Camera lens;                  ///< as loaded: its projection; eye, target and up are replaced
    DMat4 restRenderFromNode{1.0};  ///< where it stands when no player moves its model
};

struct TimelineSpec {
    CameraTracks camera;
    std::optional<FileCamera> fileCamera;
    std::vector<LightTracks> lights;
    std::optional<Turntable> turntable;
    std::vector<Light> restLights;  ///< lights as loaded: follow-camera turntables, what visibility gives back
    std::vector<GltfAnimationPlayer> players;
};

/// Frame range and content of a timeline.
struct ParsedTimeline {
    TimelineSpec spec;
    int frames = 1;
    double fps = 30.0;
    double t0 = 0.0;
};


/// Default turntable of a bare glTF model: 4 s at 30 fps (120 frames), 20° elevation, distance
/// auto fitted to the model's silhouette over the orbit, lights following the camera.
TurntableSettings defaultModelTurntable();

/// Interprets source.sections (see timeline_parse.cpp for the format). fps > 0 replaces the
/// sections' frame rate. Throws InputError naming the file and the key.
ParsedTimeline parseTimeline(const Scene& scene, const TimelineSource& source, double fps = 0.0);

/// The scene's bounds grown by where the players move the animated meshes over a film of
/// `frames` frames at `fps` (sampled at up to 256 of its frames).
Aabb filmBounds(const Scene& scene, const std::vector<GltfAnimationPlayer>& players, int frames, double fps);

/// A turntable of `s` framed on the film: the scene's bounds grown by the players' motion
/// (filmBounds), and, for films up to kMaxFramedFrames frames, each frame's camera fitted to
/// that frame's pose of the moving meshes (GltfAnimationPlayer::visitPosed).
Turntable framedOnFilm(const TurntableSettings& s, const Scene& scene, const std::vector<GltfAnimationPlayer>& players);
constexpr int kMaxFramedFrames = 4096;

/// Every model with animations plays its default ones (defaultAnimations), looped, or the one
/// `animation` (the command line's --animation) names, or all of them for "all".
std::vector<GltfAnimationPlayer> defaultPlayers(const Scene& scene, const std::optional<std::string>& animation = {});

/// Every model with animations plays the one `choice` names (chooseAnimation), looped; "all"
/// (kAllAnimations, unless a model has an animation of that name): all of its own. Throws
/// InputError(file, where: …) when a model lacks it (listing what it has) or none has any.
std::vector<GltfAnimationPlayer> chosenPlayers(const Scene& scene, const std::string& choice, const std::string& file,
                                               const std::string& where);

/// The longest clip period (GltfAnimationPlayer::period) among players; 0 without any.
double longestPeriod(const std::vector<GltfAnimationPlayer>& players);

}  // namespace rf::anim
