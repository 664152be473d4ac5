#include "exposure_meter.h"

#include <cstdio>
#include <set>

#include "cli.h"
#include "exposure.h"
#include "render.h"

namespace rf::cli {

void resolveAutoExposure(const Scene& scene, const anim::Timeline& timeline, RenderSettings& settings, int threads,
                         const std::function<void(Scene&)>& afterPose) {
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
    // Posed on a copy: posing leaves traces in a scene (its BVH is refitted, not rebuilt), and a
    // farm worker that never metered must render the same frames as rank 0.
    Scene probe = scene;
    ExposureMeter meter;
    RayStats rays;
    for (int f : frames) {
        timeline.applyFrame(probe, f);
        if (afterPose) afterPose(probe);
        meter.add(renderFrame(probe, probe.camera, small, f, threads, rays));
    }
    settings.exposure = meter.ev();
    settings.autoExposure = false;
    char text[96];
    std::snprintf(text, sizeof text, "EV %+.2f, metered once over %zu frame%s of the film", double(settings.exposure),
                  frames.size(), frames.size() == 1 ? "" : "s");
    printLine("auto exposure", text);
}

}  // namespace rf::cli
