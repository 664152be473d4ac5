#include "farm/cli/exposure_meter.h"

#include <cstdio>
#include <set>

#include "farm/cli/cli.h"
#include "engine/lights/exposure.h"
#include "engine/util/load_control.h"
#include "engine/integrators/render.h"

namespace rf::cli {

std::string noLightWarning(const Scene& scene) {
    std::string s = "auto exposure: the metered frames hold no light at all; ";
    if (scene.lights.empty()) return s + "the scene has no lights and no environment";
    s += "lights: ";
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const Light& l = scene.lights[i];
        const bool directional = l.type == LightType::Directional;
        const char* type = directional ? "directional" : l.type == LightType::Spot ? "spot" : "point";
        char buf[160];
        if (l.photometric)  // back to the file's own units (the loader divided by 683 lm/W)
            std::snprintf(buf, sizeof buf, "%s%s (%s, %g %s)", i ? ", " : "", l.name.empty() ? "unnamed" : l.name.c_str(), type,
                          double(l.intensity) * double(kLumensPerWatt), directional ? "lx" : "cd");
        else
            std::snprintf(buf, sizeof buf, "%s%s (%s, intensity %g, unitless)", i ? ", " : "",
                          l.name.empty() ? "unnamed" : l.name.c_str(), type, double(l.intensity));
        s += buf;
    }
    return s;
}

void resolveAutoExposure(Scene& scene, const anim::Timeline& timeline, RenderSettings& settings, int threads,
                         const std::function<void(Scene&)>& afterPose,
                         const std::shared_ptr<SceneCacheSlot>& bounceSlot) {
    if (!settings.autoExposure) return;
    // Four frames a quarter turn apart see every side of a turntable; 80 pixels across and one
    // sample are plenty for a log-average, and cost a few milliseconds.
    const int n = std::max(1, timeline.frameCount());
    std::set<int> frames;
    for (int k = 0; k < 4; ++k) frames.insert(timeline.isStill() ? 0 : k * n / 4);
    RenderSettings small = settings;
    small.width = std::min(settings.width, 80);
    small.height = std::max(1, int(std::lround(double(settings.height) * small.width / settings.width)));
    small.spp = 1;
    // Unpruned: the pruning rule compares a light's worth after exposure, which is what the
    // meter is about to choose; at EV 0 a scene in small units (a 10 cd lamp) would meter black.
    small.minWeight = 0.f;
    // A farm worker that never metered must render the same frames as rank 0: the scene is
    // posed on a copy when posing leaves traces (a model's animation refits its BVH), else
    // in place with its camera and lights put back (anim::TrialPose).
    LoadStep step("metering the exposure");  // part of the set-up a signal cuts short
    anim::TrialPose trial(scene, timeline, bool(afterPose));
    Scene& probe = trial.scene();
    ExposureMeter meter;
    RayStats rays;
    RenderView view{probe.camera, small};
    if (bounceSlot) view.bounceSlot = bounceSlot;
    for (int f : frames) {
        pollLoadCancel();
        timeline.applyFrame(probe, f);
        if (afterPose) afterPose(probe);
        view.camera = probe.camera;
        meter.add(renderFrame(probe, view, f, threads, rays));
    }
    settings.exposure = meter.ev();
    settings.autoExposure = false;
    if (meter.pixels() == 0) printLine("warning", noLightWarning(scene));
    char text[96];
    std::snprintf(text, sizeof text, "EV %+.2f, metered once over %zu frame%s of the film", double(settings.exposure),
                  frames.size(), frames.size() == 1 ? "" : "s");
    printLine("auto exposure", text);
}

}  // namespace rf::cli
