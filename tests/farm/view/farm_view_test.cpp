// The window's backend over the farm's one entry point (runFarm's view session): alone (a
// one-rank loopback, rank 0 rendering on its threads) and over a loopback farm of three ranks
// whose workers run runViewWorker, as under mpirun.
#include "farm/view/farm_view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <set>
#include <thread>

#include "engine/util/file_source.h"
#include "engine/util/image.h"
#include "farm/cluster/loopback_transport.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "farm/view/view_worker.h"

namespace rf::view {
namespace {

LoadedScene whitted() {
    DiskFileSource fs;
    return loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", fs);
}

RenderSettings sized(const Scene& scene, int width, int height, int spp) {
    RenderSettings s = scene.settings;
    s.width = width;
    s.height = height;
    s.spp = spp;
    return s;
}

/// Collects published frames (they come on the farm's thread) and lets the test wait.
struct Inbox {
    std::mutex m;
    std::condition_variable cv;
    std::vector<ViewFrame> frames;
    std::optional<SessionEnd> end;
    void put(ViewFrame&& f) {
        std::lock_guard<std::mutex> lock(m);
        frames.push_back(std::move(f));
        cv.notify_all();
    }
    void ended(const SessionEnd& e) {
        std::lock_guard<std::mutex> lock(m);
        end = e;
        cv.notify_all();
    }
    bool waitFor(double seconds, const std::function<bool(const ViewFrame&)>& pred) {
        std::unique_lock<std::mutex> lock(m);
        return cv.wait_for(lock, std::chrono::duration<double>(seconds), [&] {
            return std::any_of(frames.begin(), frames.end(), pred);
        });
    }
    bool waitFinal(uint64_t epoch, double seconds) {
        return waitFor(seconds, [&](const ViewFrame& f) { return f.epoch == epoch && f.final; });
    }
    const ViewFrame* lastComplete(uint64_t epoch) {
        const ViewFrame* last = nullptr;
        for (const ViewFrame& f : frames)
            if (f.epoch == epoch && f.complete) last = &f;
        return last;
    }
};

/// FarmView on rank 0 of `ranks` loopback ranks (1: alone, no transport), the others serving
/// runViewWorker on threads.
struct Farm {
    farm::LoopbackHub hub;
    farm::LoopbackTransport t0;
    std::vector<std::unique_ptr<farm::LoopbackTransport>> ts;
    std::vector<std::thread> workers;
    std::vector<int> status;
    Inbox inbox;
    std::unique_ptr<FarmView> view;

    Farm(int ranks, const LoadedScene& scene, const RenderSettings& s, int threads = 1, bool serve = true)
        : hub(ranks), t0(hub, 0), status(size_t(ranks), -1) {
        for (int r = 1; r < ranks && serve; ++r) {
            ts.push_back(std::make_unique<farm::LoopbackTransport>(hub, r));
            workers.emplace_back([this, r, scene, s] { status[size_t(r)] = runViewWorker(*ts[size_t(r - 1)], scene, s, 1); });
        }
        view = std::make_unique<FarmView>(ranks > 1 ? &t0 : nullptr, scene, s, threads,
                                          [this](ViewFrame&& f) { inbox.put(std::move(f)); },
                                          [this](const SessionEnd& e) { inbox.ended(e); });
    }
    void stop() {
        view.reset();  // tells every rank to stop
        for (auto& w : workers) w.join();
    }
};

/// still's picture of frame `frame` through the timeline's camera.
std::vector<uint8_t> stillOf(LoadedScene loaded, const RenderSettings& s, int frame) {
    Scene& scene = loaded.scene;
    anim::Timeline::fromScene(loaded).applyFrame(scene, frame);
    RayStats rays;
    return toRgb8(renderFrame(scene, {scene.camera, s}, frame, 1, rays), s);
}

class FarmViewRanks : public ::testing::TestWithParam<int> {};

TEST_P(FarmViewRanks, PictureAtRestIsTheStillBitForBit) {
    const int ranks = GetParam();
    const LoadedScene scene = whitted();
    const RenderSettings s = sized(scene.scene, 150, 70, 4);  // 150: not a multiple of the work items
    Farm farm(ranks, scene, s, 2);
    ViewRequest q;
    q.frame = 5;
    q.followTimeline = true;
    const uint64_t e = farm.view->request(q);
    ASSERT_TRUE(farm.inbox.waitFinal(e, 60.0)) << farm.view->error();
    {
        std::lock_guard<std::mutex> lock(farm.inbox.m);
        std::vector<int> spps;
        for (const ViewFrame& f : farm.inbox.frames)
            if (f.epoch == e && f.complete) spps.push_back(f.spp);
        EXPECT_EQ(spps, (std::vector<int>{1, 4}));  // refined in passes, the last at the target
        const ViewFrame* last = farm.inbox.lastComplete(e);
        ASSERT_EQ(last->width, 150);
        EXPECT_TRUE(last->rgb == stillOf(scene, s, 5));
        // The tint grid names the ranks that rendered: rank 0 alone, the workers under mpirun.
        const std::set<int> tinted(last->tileRank.begin(), last->tileRank.end());
        const std::set<int> want = ranks == 1 ? std::set<int>{0} : std::set<int>{1, 2};
        EXPECT_EQ(tinted, want);
    }
    farm.stop();
    for (int r = 1; r < ranks; ++r) EXPECT_EQ(farm.status[size_t(r)], 0) << "rank " << r;
}

TEST_P(FarmViewRanks, ANewRequestCancelsTheWorkInFlight) {
    const int ranks = GetParam();
    const LoadedScene scene = whitted();
    const RenderSettings s = sized(scene.scene, 320, 180, 1024);  // seconds of work at rest: it must not run to the end
    Farm farm(ranks, scene, s, 2);
    ViewRequest rest;
    rest.followTimeline = true;
    const uint64_t slow = farm.view->request(rest);
    // Its first pass (1 spp) is done: the ranks are now deep in the slower ones.
    ASSERT_TRUE(farm.inbox.waitFor(30.0, [&](const ViewFrame& f) { return f.epoch == slow && f.complete; })) << farm.view->error();
    ViewRequest moving = rest;
    moving.moving = true;
    const auto t0 = Clock::now();
    const uint64_t fast = farm.view->request(moving);
    ASSERT_TRUE(farm.inbox.waitFinal(fast, 30.0)) << farm.view->error();
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 10.0);  // a 1 spp frame, not 1024 spp
    {
        std::lock_guard<std::mutex> lock(farm.inbox.m);
        for (const ViewFrame& f : farm.inbox.frames) EXPECT_FALSE(f.epoch == slow && f.final);
        for (const ViewFrame& f : farm.inbox.frames) {
            EXPECT_TRUE(f.epoch != fast || f.spp == 1) << f.spp;
        }
    }
    farm.stop();
    for (int r = 1; r < ranks; ++r) EXPECT_EQ(farm.status[size_t(r)], 0) << "rank " << r;
}

INSTANTIATE_TEST_SUITE_P(View, FarmViewRanks, ::testing::Values(1, 3));

TEST(FarmView, ATimelineChangeReachesEveryRank) {
    // The window's keys replace the timeline: the next picture is posed by the new one on every
    // rank (here: the scene without its timeline, i.e. its camera as loaded).
    const LoadedScene scene = whitted();
    const RenderSettings s = sized(scene.scene, 96, 54, 1);
    Farm farm(3, scene, s);
    farm.view->setTimeline("");
    ViewRequest q;
    q.frame = 7;
    q.followTimeline = true;
    const uint64_t e = farm.view->request(q);
    ASSERT_TRUE(farm.inbox.waitFinal(e, 60.0)) << farm.view->error();
    LoadedScene still = scene;
    still.timeline.sections = nullptr;
    {
        std::lock_guard<std::mutex> lock(farm.inbox.m);
        EXPECT_TRUE(farm.inbox.lastComplete(e)->rgb == stillOf(still, s, 7));
        EXPECT_FALSE(farm.inbox.lastComplete(e)->rgb == stillOf(scene, s, 7));
    }
    farm.stop();
}

TEST(FarmView, ASilentRankIsReported) {
    const LoadedScene scene = whitted();
    const RenderSettings s = sized(scene.scene, 256, 64, 1);  // four 64-pixel tiles: both ranks get some
    // Rank 1 never answers: no worker runs on it.
    Farm farm(2, scene, s, 1, false);
    ViewRequest q;
    q.followTimeline = true;
    farm.view->request(q);
    std::unique_lock<std::mutex> lock(farm.inbox.m);
    ASSERT_TRUE(farm.inbox.cv.wait_for(lock, std::chrono::seconds(15), [&] { return farm.inbox.end.has_value(); }));
    EXPECT_EQ(farm.inbox.end->lostRank, 1);
    EXPECT_FALSE(farm.inbox.end->signalled);
    EXPECT_EQ(farm.inbox.end->error.rfind("rank 1 stopped answering (silent for ", 0), 0u) << farm.inbox.end->error;
    EXPECT_EQ(farm.view->error(), farm.inbox.end->error);
    // Rank 0 renders too at two ranks, but the pass needs rank 1's tiles: never a whole picture.
    for (const ViewFrame& f : farm.inbox.frames) EXPECT_FALSE(f.complete);
}

}  // namespace
}  // namespace rf::view
