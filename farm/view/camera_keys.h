#pragma once
/// Camera keys authored in the viewer, and the scene file they are saved in: the source scene
/// with a "timeline" section (anim/timeline_format.md) whose camera tracks are the keys, so that
/// `rayfarm render` of the saved file renders the path the window plays.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "engine/load/loaded_scene.h"
#include "engine/scene/scene.h"
#include "anim/timeline.h"

namespace rf::view {

/// A camera pose at a time of the film, in world space (render origin added back).
struct CameraKey {
    double time = 0.0;
    DVec3 eye{0.0}, target{0.0};
    double fovDeg = 45.0;
};

/// Keys in increasing time; one key per time.
class CameraKeys {
public:
    /// Adds the key, replacing one at the same time; returns its index.
    int add(const CameraKey& k);
    void remove(int index);
    const std::vector<CameraKey>& keys() const { return keys_; }
    bool empty() const { return keys_.empty(); }

private:
    std::vector<CameraKey> keys_;
};

/// The key for the render-space camera c at time t.
CameraKey keyFromCamera(const Camera& c, const DVec3& renderOrigin, double t);

/// The film the viewer scrubs: the scene's timeline, or 4 s at 30 fps for a still scene (so
/// keys can be placed in time). frames × 1/fps from the timeline's start.
struct Film {
    int frames = 1;
    double fps = 30.0;
};
Film filmOf(const anim::Timeline& tl);

/// The "timeline" section for the keys: the scene's own timeline (source) with its camera
/// replaced by position/target/fov tracks (catmull-rom through the keys), or for a turntable or
/// none, a new one with the film's fps and frame count and the same model animation.
nlohmann::json keyedTimeline(const CameraKeys& keys, const TimelineSource& source, const Film& film);

/// A timeline as it travels to the view's ranks: its sections serialised ("" for none).
std::string sectionsText(const TimelineSource& source);
/// base with the sections of sectionsText's text in place (the command line's --animation kept;
/// its --camera too, unless the text differs from base's own sections: keys made in the window
/// replace the file's camera).
TimelineSource withSections(const TimelineSource& base, const std::string& text);

/// The scene file to save: a JSON scene keeps everything but its timeline; a bare glTF model
/// becomes a scene holding the model (absolute path), its camera, background and light rig.
/// settings become the file's "render" section.
nlohmann::json sceneDocument(const Scene& scene, const RenderSettings& settings, const nlohmann::json& timeline);

/// Writes doc to path (JSON, 2-space indent); throws std::runtime_error naming the path.
void writeSceneFile(const std::string& path, const nlohmann::json& doc);

}  // namespace rf::view
