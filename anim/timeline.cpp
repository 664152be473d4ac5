#include "anim/timeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "anim/frame_time.h"
#include "engine/util/model_path.h"
#include "anim/timeline_spec.h"

namespace rf::anim {

namespace {

void applyCamera(const CameraTracks& c, Scene& scene, double t) {
    if (!c.any()) return;
    Camera& cam = scene.camera;
    const DVec3 o = scene.renderOrigin;
    DVec3 eye(cam.eye);
    if (c.orbit) {
        // The POV-Ray form, in double: x = r·sin 2πc, z = −r·cos 2πc (c = 0 sits on −z).
        const double turns = c.orbit->phase + t / c.orbit->period;
        const double a = 2.0 * 3.14159265358979323846 * turns;
        eye = c.orbit->center - o + DVec3(c.orbit->radius * std::sin(a), c.orbit->height, -c.orbit->radius * std::cos(a));
    } else if (c.position) {
        eye = c.position->evaluateVec3(t);  // already rebased at parse time
    }
    cam.eye = Vec3(eye);
    if (c.orientation) {
        const DQuat q = c.orientation->evaluateQuat(t);
        cam.target = Vec3(eye + q * DVec3(0.0, 0.0, -1.0));
        cam.up = Vec3(q * DVec3(0.0, 1.0, 0.0));
    } else {
        if (c.target) cam.target = Vec3(c.target->evaluateVec3(t));
        if (c.up) {
            const DVec3 up = c.up->evaluateVec3(t);
            if (glm::length(up) > 0.0) cam.up = Vec3(glm::normalize(up));  // lookAt copes with parallel
        }
    }
    if (c.fov) cam.fovDeg = static_cast<float>(std::clamp(c.fov->evaluateScalar(t), 1e-3, 179.0));
}

void applyLight(const LightTracks& lt, const Light& rest, Light& l, double t) {
    if (lt.position) l.position = Vec3(lt.position->evaluateVec3(t));
    if (lt.direction) {
        // Interpolating opposite keys can pass through zero; keep the loaded direction there.
        const DVec3 d = lt.direction->evaluateVec3(t);
        const double len = glm::length(d);
        l.direction = len > 1e-12 ? Vec3(d / len) : rest.direction;
    }
    if (lt.color) l.color = glm::max(Color(lt.color->evaluateVec3(t)), Color(0.f));  // splines may overshoot
    if (lt.intensity) l.intensity = static_cast<float>(std::max(0.0, lt.intensity->evaluateScalar(t)));
    if (lt.outerDeg) l.outerCone = static_cast<float>(glm::radians(std::clamp(lt.outerDeg->evaluateScalar(t), 0.0, 90.0)));
    if (lt.innerDeg) l.innerCone = static_cast<float>(glm::radians(std::clamp(lt.innerDeg->evaluateScalar(t), 0.0, 90.0)));
    l.innerCone = std::min(l.innerCone, l.outerCone);
}

}  // namespace


Timeline Timeline::fromScene(const Scene& scene, const TimelineSource& source, double fps) {
    Timeline tl;
    ParsedTimeline p;
    if (source.sections) {
        p = parseTimeline(scene, source, fps);
    } else if (isGltfPath(scene.sourcePath)) {
        p.spec.restLights = scene.lights;
        TurntableSettings s = defaultModelTurntable();
        if (fps > 0.0) s.fps = fps;
        p.spec.players = defaultPlayers(scene, source.animation);
        // One orbit over a whole number of plays of the clip: the film loops seamlessly.
        s.seconds = filmSecondsForClip(longestPeriod(p.spec.players), s.seconds);
        p.spec.turntable = framedOnFilm(s, scene, p.spec.players);
        p.frames = p.spec.turntable->frameCount();
        p.fps = s.fps;
    } else {
        // One still frame; a model's own animation is still posed at t = 0.
        p.spec.players = defaultPlayers(scene, source.animation);
    }
    tl.frames_ = p.frames;
    tl.fps_ = p.fps;
    tl.t0_ = p.t0;
    const TimelineSpec& s = p.spec;
    if (s.camera.any() || !s.lights.empty() || s.turntable || !s.players.empty())
        tl.spec_ = std::make_shared<const TimelineSpec>(std::move(p.spec));
    return tl;
}

double Timeline::frameTime(int frame) const { return anim::frameTime(t0_, fps_, frame); }

std::vector<Timeline::Clip> Timeline::clips() const {
    std::vector<Clip> out;
    if (spec_)
        for (const GltfAnimationPlayer& p : spec_->players) out.push_back({p.model(), p.animation(), p.period()});
    return out;
}

bool Timeline::animatesGeometry() const { return spec_ && !spec_->players.empty(); }

void Timeline::apply(Scene& scene, double t) const {
    if (!spec_) return;
    const TimelineSpec& s = *spec_;
    if (s.turntable) s.turntable->apply(scene, t, s.restLights);
    applyCamera(s.camera, scene, t);
    for (const LightTracks& lt : s.lights)
        if (lt.light < static_cast<int>(scene.lights.size()))
            applyLight(lt, s.restLights[lt.light], scene.lights[lt.light], t);
    for (const GltfAnimationPlayer& pl : s.players) pl.apply(scene, t);
}

}  // namespace rf::anim
