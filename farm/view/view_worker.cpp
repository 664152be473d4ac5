#include "farm/view/view_worker.h"

#include <algorithm>
#include <memory>

#include <nlohmann/json.hpp>

#include "farm/process/interrupt.h"
#include "farm/cluster/messages.h"
#include "farm/cluster/render_engine.h"
#include "farm/cluster/worker.h"
#include "farm/view/camera_keys.h"

namespace rf::view {

namespace {
/// A worker whose rank 0 is silent this long leaves (runWorker's masterTimeout); rank 0 tells
/// it every half second that it lives, idle or not.
constexpr double kMasterTimeout = 20.0;
}  // namespace

int runViewWorker(farm::Transport& t, LoadedScene loaded, RenderSettings settings, int threads) {
    farm::installInterruptHandlers();
    try {
        const Scene pristine = loaded.scene;
        farm::RenderEngine engine(std::move(loaded.scene), anim::Timeline::fromScene(pristine, loaded.timeline), settings,
                                  std::max(1, threads));
        auto retime = [&](const farm::Message& m) {
            if (m.tag != farm::kTagViewTimeline) return;
            // A new timeline poses the scene as loaded, not as the old one left it.
            anim::Timeline timeline = anim::Timeline::fromScene(pristine, view::withSections(loaded.timeline, m.bytes));
            engine.setScene(Scene(pristine), std::move(timeline));
        };
        return farm::runWorker(t, engine, kMasterTimeout, retime);
    } catch (const std::exception& e) {
        farm::reportWorkerError(t, e.what());
        return 1;
    }
}

}  // namespace rf::view
