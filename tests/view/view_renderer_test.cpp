#include "view_renderer.h"

#include <gtest/gtest.h>

#include <condition_variable>
#include <functional>
#include <mutex>

#include "file_source.h"
#include "image.h"
#include "render.h"
#include "scene_loader.h"

namespace rf::view {
namespace {

Scene whitted() {
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

/// Collects published frames and lets the test wait for one that matches.
struct Inbox {
    std::mutex m;
    std::condition_variable cv;
    std::vector<ViewFrame> frames;
    void put(ViewFrame&& f) {
        std::lock_guard<std::mutex> lock(m);
        frames.push_back(std::move(f));
        cv.notify_all();
    }
    bool waitFor(double seconds, const std::function<bool(const ViewFrame&)>& pred) {
        std::unique_lock<std::mutex> lock(m);
        return cv.wait_for(lock, std::chrono::duration<double>(seconds), [&] {
            for (const ViewFrame& f : frames)
                if (pred(f)) return true;
            return false;
        });
    }
    bool waitFinal(uint64_t epoch, double seconds) {
        return waitFor(seconds, [&](const ViewFrame& f) { return f.epoch == epoch && f.final; });
    }
};

TEST(ViewRenderer, RefinementPassesEndAtTheTarget) {
    EXPECT_EQ(refinementSpp(1), (std::vector<int>{1}));
    EXPECT_EQ(refinementSpp(9), (std::vector<int>{1, 4, 9}));
    EXPECT_EQ(refinementSpp(16), (std::vector<int>{1, 4, 16}));
    EXPECT_EQ(refinementSpp(64), (std::vector<int>{1, 4, 16, 64}));
}

TEST(ViewRenderer, MovingResolutionHoldsTheFrameTime) {
    // Over the budget: half the resolution (down to a quarter); far under it: back up.
    EXPECT_EQ(nextMovingScale(1, kMovingFrameMs + 5.0), 2);
    EXPECT_EQ(nextMovingScale(2, kMovingFrameMs + 5.0), 4);
    EXPECT_EQ(nextMovingScale(4, 10.0 * kMovingFrameMs), 4);
    EXPECT_EQ(nextMovingScale(4, 0.1 * kMovingFrameMs), 2);
    // In between (4x the pixels would overrun): stay.
    EXPECT_EQ(nextMovingScale(2, 0.5 * kMovingFrameMs), 2);
    EXPECT_EQ(nextMovingScale(1, 0.1 * kMovingFrameMs), 1);
}

TEST(ViewRenderer, PictureAtRestIsTheStillBitForBit) {
    Scene scene = whitted();
    const anim::Timeline tl = anim::Timeline::fromScene(scene);
    const RenderSettings s = sized(scene, 96, 54, 4);
    tl.applyFrame(scene, 3);
    RayStats rays;
    const std::vector<uint8_t> still = toRgb8(renderFrame(scene, scene.camera, s, 3, 2, rays), s.toneMap);

    Inbox inbox;
    ViewRenderer r(scene, tl, s, 2, [&](ViewFrame&& f) { inbox.put(std::move(f)); });
    ViewRequest q;
    q.frame = 3;
    q.followTimeline = true;
    const uint64_t e = r.request(q);
    ASSERT_TRUE(inbox.waitFinal(e, 60.0)) << r.error();
    std::lock_guard<std::mutex> lock(inbox.m);
    const ViewFrame* last = nullptr;
    std::vector<int> spps;
    for (const ViewFrame& f : inbox.frames)
        if (f.complete) {
            spps.push_back(f.spp);
            last = &f;
        }
    EXPECT_EQ(spps, (std::vector<int>{1, 4}));  // refined in passes, the last at the target
    ASSERT_EQ(last->width, 96);
    EXPECT_TRUE(last->rgb == still);
}

TEST(ViewRenderer, ANewRequestCancelsTheWorkInFlight) {
    Scene scene = whitted();
    const anim::Timeline tl = anim::Timeline::fromScene(scene);
    const RenderSettings s = sized(scene, 320, 180, 1024);  // seconds of work at rest: it must not run to the end
    Inbox inbox;
    ViewRenderer r(scene, tl, s, 2, [&](ViewFrame&& f) { inbox.put(std::move(f)); });
    ViewRequest rest;
    rest.followTimeline = true;
    const uint64_t slow = r.request(rest);
    // Its first pass (1 spp) is done: the render thread is now deep in the slower ones.
    ASSERT_TRUE(inbox.waitFor(30.0, [&](const ViewFrame& f) { return f.epoch == slow && f.complete; })) << r.error();
    ViewRequest moving = rest;
    moving.moving = true;
    const auto t0 = Clock::now();
    const uint64_t fast = r.request(moving);
    ASSERT_TRUE(inbox.waitFinal(fast, 30.0)) << r.error();
    const double waited = std::chrono::duration<double>(Clock::now() - t0).count();
    EXPECT_LT(waited, 10.0);  // a 1 spp frame, not the 1024 spp one in front of it
    std::lock_guard<std::mutex> lock(inbox.m);
    for (const ViewFrame& f : inbox.frames) EXPECT_FALSE(f.epoch == slow && f.final);
    for (const ViewFrame& f : inbox.frames)
        if (f.epoch == fast) EXPECT_EQ(f.spp, 1);
}

}  // namespace
}  // namespace rf::view
