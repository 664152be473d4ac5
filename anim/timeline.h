#pragma once
/// The timeline: for any frame index, the camera, the lights and the model's animated nodes, as
/// a pure function of the index. Any rank can render any frame with no state carried over.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/load/loaded_scene.h"
#include "engine/scene/scene.h"

namespace rf::anim {

struct TimelineSpec;

class Timeline {
public:
    /// Interprets what the loader found beside the scene (its "timeline" / "turntable"
    /// sections, --animation). A JSON scene without sections is a single still frame; a bare
    /// glTF model (.gltf/.glb) gets the default turntable (4 s at 30 fps = 120 frames); with
    /// source.camera the film looks through that glTF camera instead, posed from its node's
    /// animation each frame, as long as that animation (both ends). fps > 0
    /// replaces the rate of the sections or of the default turntable (render --fps). Throws
    /// InputError naming the scene file and the key.
    static Timeline fromScene(const Scene& scene, const TimelineSource& source, double fps = 0.0);
    static Timeline fromScene(const LoadedScene& loaded, double fps = 0.0) { return fromScene(loaded.scene, loaded.timeline, fps); }

    int frameCount() const { return frames_; }
    double fps() const { return fps_; }
    /// t0 + i / fps, computed from the index.
    double frameTime(int frame) const;
    /// Sets the scene's camera, lights and animated nodes to their state at time t (seconds).
    /// Overwrites absolute values only, so the result depends on t and the loaded scene alone.
    void apply(Scene& scene, double t) const;
    void applyFrame(Scene& scene, int frame) const { apply(scene, frameTime(frame)); }

    /// True when some model animation plays (meshes move and the BVH is refit per frame).
    bool animatesGeometry() const;
    /// A model animation the film plays: which, and seconds of film one play of it takes.
    struct Clip {
        int model = 0, animation = 0;
        double period = 0.0;
    };
    std::vector<Clip> clips() const;
    /// True when nothing changes from frame to frame.
    bool isStill() const { return !spec_; }
    /// The glTF camera the film looks through (TimelineSource::camera), if one.
    std::optional<int> fileCamera() const;
    /// Seconds of the animation that moves that camera (0: it stands still, or no file camera).
    double fileCameraPeriod() const;
    /// True when apply() changes more of a scene than its camera and lights: a model's
    /// animation poses nodes (its meshes, a refitted BVH) and materials.
    bool posesModels() const;

private:
    int frames_ = 1;
    double fps_ = 30.0;
    double t0_ = 0.0;
    double fileCameraPeriod_ = 0.0;
    std::shared_ptr<const TimelineSpec> spec_;  ///< null: a still frame, apply() does nothing
};

/// A scene posed for a look at a few frames (exposure metering, `info`), left as it was
/// afterwards. A timeline that moves only the camera and the lights poses the scene itself and
/// puts those two back when the TrialPose goes; one that poses models works on a copy, since
/// posing leaves traces (a refitted BVH) and the frames rendered later must not depend on
/// whether this look happened. So a big model that does not move is not copied for a look.
class TrialPose {
public:
    TrialPose(Scene& scene, const Timeline& timeline, bool copy = false);
    ~TrialPose();
    TrialPose(const TrialPose&) = delete;
    TrialPose& operator=(const TrialPose&) = delete;
    /// The scene to pose and render.
    Scene& scene() { return copy_ ? *copy_ : original_; }
    bool copied() const { return bool(copy_); }

private:
    Scene& original_;
    std::unique_ptr<Scene> copy_;
    Camera camera_;
    std::vector<Light> lights_;
};

}  // namespace rf::anim
