#include "farm/view/view_worker.h"

#include <algorithm>
#include <memory>

#include <nlohmann/json.hpp>

#include "farm/process/interrupt.h"
#include "farm/cluster/messages.h"
#include "farm/cluster/render_engine.h"
#include "farm/cluster/worker.h"

namespace rf::view {

namespace {
/// A worker whose rank 0 is silent this long leaves (runWorker's masterTimeout); rank 0 tells
/// it every half second that it lives, idle or not.
constexpr double kMasterTimeout = 20.0;
}  // namespace

int runViewWorker(farm::Transport& t, Scene scene, RenderSettings settings, int threads) {
    farm::installInterruptHandlers();
    try {
        const Scene pristine = scene;
        farm::RenderEngine engine(std::move(scene), anim::Timeline::fromScene(pristine), settings, std::max(1, threads));
        auto retime = [&](const farm::Message& m) {
            if (m.tag != farm::kTagViewTimeline) return;
            Scene keyed = pristine;  // a new timeline poses the scene as loaded, not as the old one left it
            keyed.timeline = m.bytes.empty() ? nullptr : std::make_shared<const nlohmann::json>(nlohmann::json::parse(m.bytes));
            anim::Timeline timeline = anim::Timeline::fromScene(keyed);
            engine.setScene(std::move(keyed), std::move(timeline));
        };
        return farm::runWorker(t, engine, kMasterTimeout, retime);
    } catch (const std::exception& e) {
        farm::reportWorkerError(t, e.what());
        return 1;
    }
}

}  // namespace rf::view
