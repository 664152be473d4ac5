#include "anim/timeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "anim/frame_time.h"
#include "engine/util/errors.h"
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

/// The players' pose of the file camera's node at t (its rest place when none moves its model).
void applyFileCamera(const FileCamera& fc, const std::vector<GltfAnimationPlayer>& players, Scene& scene, double t) {
    for (const GltfAnimationPlayer& p : players) {
        if (p.model() != fc.model || fc.model < 0 || size_t(fc.model) >= scene.geometry.models.size()) continue;
        std::vector<DMat4> renderFromNode;
        std::vector<std::vector<double>> weights;
        p.pose(scene.geometry.models[size_t(fc.model)], t, renderFromNode, weights);
        if (fc.node >= 0 && size_t(fc.node) < renderFromNode.size()) {
            Camera lens = fc.lens;
            p.applyCamera(fc.source, t, lens);
            scene.camera = cameraOnNode(lens, renderFromNode[size_t(fc.node)]);
            return;
        }
    }
    scene.camera = cameraOnNode(fc.lens, fc.restRenderFromNode);
}

/// The file camera `index` of the scene, checked (chosenGltfCamera's refusals, by `where`).
FileCamera chosenFileCamera(const Scene& scene, int index, const std::string& where) {
    const int n = int(scene.gltfCameras.size());
    if (index < 0 || index >= n)
        throw InputError(scene.sourcePath, where + ": no camera " + std::to_string(index) + " (the file has " +
                                               std::to_string(n) + (n == 1 ? " camera)" : " cameras)"));
    if (size_t(index) < scene.gltfCameraFaults.size() && !scene.gltfCameraFaults[size_t(index)].second.empty()) {
        const auto& [file, fault] = scene.gltfCameraFaults[size_t(index)];
        throw InputError(file, fault + "; choose another " + where);
    }
    FileCamera fc;
    fc.index = index;
    fc.lens = scene.gltfCameras[size_t(index)];
    if (size_t(index) < scene.gltfCameraNodes.size()) {
        fc.model = scene.gltfCameraNodes[size_t(index)].model;
        fc.node = scene.gltfCameraNodes[size_t(index)].node;
        fc.source = scene.gltfCameraNodes[size_t(index)].camera;
    }
    if (fc.model >= 0 && size_t(fc.model) < scene.geometry.models.size()) {
        const SceneGraph& g = scene.geometry.models[size_t(fc.model)];
        std::vector<DMat4> local(g.nodes.size());
        for (size_t i = 0; i < g.nodes.size(); ++i) local[i] = nodeLocalMatrix(g.nodes[i]);
        const std::vector<DMat4> world = modelFromNode(g, local);
        if (fc.node >= 0 && size_t(fc.node) < world.size()) fc.restRenderFromNode = g.renderFromModel * world[size_t(fc.node)];
    } else {
        fc.model = -1;  // placed where it was loaded, never moved
    }
    if (fc.model < 0) {
        // No node to follow: the loaded camera's own frame.
        const CameraBasis b = lookAt(fc.lens.eye, fc.lens.target, fc.lens.up);
        fc.restRenderFromNode = DMat4(glm::dvec4(DVec3(b.right), 0.0), glm::dvec4(DVec3(b.up), 0.0), glm::dvec4(-DVec3(b.forward), 0.0),
                                      glm::dvec4(DVec3(fc.lens.eye), 1.0));
    }
    return fc;
}

/// Seconds the file camera's animation lasts under these players (the longest animation that
/// moves its node or a node above it); 0 when it stands still.
double cameraMovingPeriod(const FileCamera& fc, const Scene& scene, const std::vector<GltfAnimationPlayer>& players) {
    double p = 0.0;
    for (const GltfAnimationPlayer& pl : players)
        if (pl.model() == fc.model && fc.model >= 0) p = std::max(p, pl.periodMoving(scene.geometry.models[size_t(fc.model)], fc.node));
    return p;
}

}  // namespace

bool Timeline::posesModels() const { return spec_ && !spec_->players.empty(); }

TrialPose::TrialPose(Scene& scene, const Timeline& timeline, bool copy) : original_(scene) {
    if (copy || timeline.posesModels()) {
        copy_ = std::make_unique<Scene>(scene);
    } else {
        camera_ = scene.camera;
        lights_ = scene.lights;
    }
}

TrialPose::~TrialPose() {
    if (copy_) return;
    original_.camera = camera_;
    original_.lights = std::move(lights_);
}

std::optional<int> Timeline::fileCamera() const {
    if (spec_ && spec_->fileCamera) return spec_->fileCamera->index;
    return std::nullopt;
}

double Timeline::fileCameraPeriod() const { return spec_ && spec_->fileCamera ? fileCameraPeriod_ : 0.0; }

Timeline Timeline::fromScene(const Scene& scene, const TimelineSource& source, double fps) {
    Timeline tl;
    ParsedTimeline p;
    std::optional<FileCamera> fc;
    if (source.camera) fc = chosenFileCamera(scene, *source.camera, source.cameraSource);
    if (source.sections) {
        p = parseTimeline(scene, source, fps);
        if (fc) {
            // The file's camera replaces the timeline's camera and turntable; its length stays.
            p.spec.camera = CameraTracks{};
            p.spec.turntable.reset();
            tl.fileCameraPeriod_ = cameraMovingPeriod(*fc, scene, p.spec.players);
        }
    } else if (fc) {
        // A film through the file's camera: as long as the animation it moves with, both ends
        // rendered (that animation holds its last key there); a camera standing still, one play
        // of the longest animation that plays, looped; nothing moving, one frame.
        p.spec.restLights = scene.lights;
        p.spec.players = defaultPlayers(scene, source.animation);
        p.fps = fps > 0.0 ? fps : 30.0;
        const double moving = cameraMovingPeriod(*fc, scene, p.spec.players);
        tl.fileCameraPeriod_ = moving;
        if (moving > 0.0 && moving <= 3600.0) {
            for (GltfAnimationPlayer& pl : p.spec.players) pl.holdEndsAt(moving);
            p.frames = anim::frameCount(moving, p.fps) + 1;
        } else if (const double clip = longestPeriod(p.spec.players); clip > 0.0 && clip <= 3600.0) {
            p.frames = std::max(1, anim::frameCount(clip, p.fps));
        }
    } else if (isModelPath(scene.sourcePath)) {
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
    if (p.spec.restLights.empty()) p.spec.restLights = scene.lights;
    tl.frames_ = p.frames;
    tl.fps_ = p.fps;
    tl.t0_ = p.t0;
    p.spec.fileCamera = fc;
    const TimelineSpec& s = p.spec;
    if (s.camera.any() || !s.lights.empty() || s.turntable || !s.players.empty() || s.fileCamera)
        tl.spec_ = std::make_shared<const TimelineSpec>(std::move(p.spec));
    return tl;
}

double Timeline::frameTime(int frame) const { return anim::frameTime(t0_, fps_, frame); }

std::vector<Timeline::Clip> Timeline::clips() const {
    std::vector<Clip> out;
    if (spec_)
        for (const GltfAnimationPlayer& p : spec_->players) {
            const std::vector<int> anims = p.animations();
            for (size_t i = 0; i < anims.size(); ++i) out.push_back({p.model(), anims[i], p.partPeriod(i)});
        }
    return out;
}

bool Timeline::animatesGeometry() const { return spec_ && !spec_->players.empty(); }

void Timeline::apply(Scene& scene, double t) const {
    if (!spec_) return;
    const TimelineSpec& s = *spec_;
    // Every light as loaded first: what the keys below set is then a function of t alone (a
    // cone clamped, a light hidden or keyed on an earlier frame leaves nothing behind).
    for (size_t i = 0; i < scene.lights.size() && i < s.restLights.size(); ++i) scene.lights[i] = s.restLights[i];
    if (s.turntable) s.turntable->apply(scene, t, s.restLights);
    applyCamera(s.camera, scene, t);
    // The models' own keys (KHR_animation_pointer), then the scene file's light tracks, which
    // override them where both key a light.
    for (const GltfAnimationPlayer& pl : s.players) pl.apply(scene, t);
    for (const LightTracks& lt : s.lights)
        if (lt.light < static_cast<int>(scene.lights.size()))
            applyLight(lt, s.restLights[lt.light], scene.lights[lt.light], t);
    if (s.fileCamera) applyFileCamera(*s.fileCamera, s.players, scene, t);
}

}  // namespace rf::anim
