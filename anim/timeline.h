#pragma once
/// The timeline: for any frame index, the camera, the lights and the model's animated nodes, as
/// a pure function of the index. Any rank can render any frame with no state carried over.
#include <string>

#include "scene.h"

namespace rf::anim {

class Timeline {
public:
    /// Parses scene.timelineJson ("timeline" / "turntable" sections). A scene without one is a
    /// single still frame. Throws InputError naming the scene file and the key on bad input.
    static Timeline fromScene(const Scene& scene);

    int frameCount() const { return frames_; }
    double fps() const { return fps_; }
    /// t0 + i / fps, computed from the index.
    double frameTime(int frame) const;
    /// Sets the scene's camera, lights and animated nodes to their state at time t (seconds).
    /// Overwrites absolute values only, so the result depends on t and the loaded scene alone.
    void apply(Scene& scene, double t) const;
    void applyFrame(Scene& scene, int frame) const { apply(scene, frameTime(frame)); }

private:
    int frames_ = 1;
    double fps_ = 30.0;
    double t0_ = 0.0;
};

}  // namespace rf::anim
