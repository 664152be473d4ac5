#include "farm/commands/worker_head_start.h"

#include "engine/integrators/bounce_cache.h"
#include "engine/util/parallel.h"
#include "farm/commands/render_options.h"

namespace rf::cli {

using namespace rf::farm;

void prebuildBounceCache(Scene& scene, const anim::Timeline& tl, const RenderSettings& settings, int frame,
                         int threads, SceneCacheSlot& bounceSlot) {
    if (settings.bounce <= 0 || !bounceApplies(scene)) return;
    anim::TrialPose trial(scene, tl);  // a model that does not move is posed in place, not copied
    tl.applyFrame(trial.scene(), frame);
    bounceCache(trial.scene(), settings, &bounceSlot, threads > 0 ? threads : hardwareThreads());
}

void workerHeadStart(LoadedScene& loaded, SceneCacheSlot& bounceSlot, const ArgParser& p, const RenderJob& job, int threads) {
    Scene& scene = loaded.scene;
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    const anim::Timeline tl = anim::Timeline::fromScene(loaded, job.fpsOption);
    int first = 0, last = tl.frameCount() - 1;
    if (auto f = p.value("--frames")) parseFrameRange(*f, tl.frameCount(), first, last);
    prebuildBounceCache(scene, tl, settings, first, threads, bounceSlot);
}

}  // namespace rf::cli
