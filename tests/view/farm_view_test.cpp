#include "farm_view.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <thread>

#include "file_source.h"
#include "image.h"
#include "loopback_transport.h"
#include "render.h"
#include "scene_loader.h"
#include "view_worker.h"

namespace rf::view {
namespace {

Scene whitted() {
    DiskFileSource fs;
    return loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", fs);
}

/// Rank 0's FarmView over a loopback hub, ranks 1..n-1 running runViewWorker on threads.
struct LoopbackFarm {
    farm::LoopbackHub hub;
    farm::LoopbackTransport t0;
    std::vector<std::unique_ptr<farm::LoopbackTransport>> ts;
    std::vector<std::thread> workers;
    std::vector<int> status;
    std::vector<ViewFrame> frames;
    std::unique_ptr<FarmView> view;

    LoopbackFarm(int ranks, const Scene& scene, const RenderSettings& s) : hub(ranks), t0(hub, 0), status(size_t(ranks), -1) {
        for (int r = 1; r < ranks; ++r) {
            ts.push_back(std::make_unique<farm::LoopbackTransport>(hub, r));
            workers.emplace_back([this, r, scene, s] { status[size_t(r)] = runViewWorker(*ts[size_t(r - 1)], scene, s, 1); });
        }
        view = std::make_unique<FarmView>(t0, s, 1, [this](ViewFrame&& f) { frames.push_back(std::move(f)); });
    }
    /// Steps rank 0 until a final frame of epoch arrives (true) or seconds pass.
    bool runUntilFinal(uint64_t epoch, double seconds) {
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end) {
            view->step();
            for (const ViewFrame& f : frames)
                if (f.epoch == epoch && f.final) return true;
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        return false;
    }
    void stop() {
        view.reset();  // tells every rank to stop
        for (auto& w : workers) w.join();
    }
};

TEST(FarmView, FrameAcrossRanksIsTheStillBitForBit) {
    Scene scene = whitted();
    const anim::Timeline tl = anim::Timeline::fromScene(scene);
    RenderSettings s = scene.settings;
    s.width = 150;  // not a multiple of the 64-pixel work items
    s.height = 70;
    s.spp = 4;
    LoopbackFarm farm(3, scene, s);
    ViewRequest q;
    q.frame = 5;
    q.followTimeline = true;
    const uint64_t e = farm.view->request(q);
    ASSERT_TRUE(farm.runUntilFinal(e, 60.0)) << farm.view->error();
    const ViewFrame& last = farm.frames.back();
    tl.applyFrame(scene, 5);
    RayStats rays;
    EXPECT_TRUE(last.rgb == toRgb8(renderFrame(scene, scene.camera, s, 5, 1, rays), s.toneMap));
    // Both workers rendered some of it, and the tint grid names only them.
    std::set<int> ranks(last.tileRank.begin(), last.tileRank.end());
    EXPECT_EQ(ranks, (std::set<int>{1, 2}));
    farm.stop();
    EXPECT_EQ(farm.status[1], 0);
    EXPECT_EQ(farm.status[2], 0);
}

TEST(FarmView, ANewRequestCancelsAcrossRanks) {
    Scene scene = whitted();
    RenderSettings s = scene.settings;
    s.width = 256;
    s.height = 128;
    s.spp = 1024;  // seconds per work item at rest
    LoopbackFarm farm(3, scene, s);
    ViewRequest rest;
    rest.followTimeline = true;
    const uint64_t slow = farm.view->request(rest);
    // Let the slow pass reach the ranks and start (its 1 spp pass completes first).
    const auto until = Clock::now() + std::chrono::seconds(20);
    while (Clock::now() < until && std::none_of(farm.frames.begin(), farm.frames.end(), [&](const ViewFrame& f) { return f.epoch == slow && f.complete; })) {
        farm.view->step();
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    for (int i = 0; i < 50; ++i) farm.view->step();  // the 4 spp pass goes out
    ViewRequest moving = rest;
    moving.moving = true;
    const auto t0 = Clock::now();
    const uint64_t fast = farm.view->request(moving);
    ASSERT_TRUE(farm.runUntilFinal(fast, 30.0)) << farm.view->error();
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 10.0);
    for (const ViewFrame& f : farm.frames) EXPECT_FALSE(f.epoch == slow && f.final);
    farm.stop();
}

TEST(FarmView, ASilentRankIsReported) {
    Scene scene = whitted();
    RenderSettings s = scene.settings;
    s.width = 64;
    s.height = 32;
    farm::LoopbackHub hub(2);
    farm::LoopbackTransport t0(hub, 0);
    std::vector<ViewFrame> frames;
    // Rank 1 never answers: no worker runs on it.
    FarmView view(t0, s, 1, [&](ViewFrame&& f) { frames.push_back(std::move(f)); });
    ViewRequest q;
    q.followTimeline = true;
    view.request(q);
    const auto end = Clock::now() + std::chrono::duration<double>(FarmView::kSilenceSeconds + 5.0);
    while (Clock::now() < end && view.error().empty()) {
        view.step();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_EQ(view.error(), "rank 1 stopped answering");
    for (const ViewFrame& f : frames) EXPECT_FALSE(f.complete);  // partial pictures only, never a whole one
}

}  // namespace
}  // namespace rf::view
