// runFarm's interactive session over the in-process transport: views posted to a ViewInbox,
// each pass an epoch (kTagView) that workers serving through runFarmWorker render with the
// view's camera and spp; a newer view cancels the work in flight on every rank, and late
// results of an older epoch never reach the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include "tests/farm/farm_test_scene.h"
#include "farm/cluster/loopback_transport.h"
#include "engine/integrators/render.h"
#include "farm/cluster/render_engine.h"
#include "farm/cluster/run_farm.h"
#include "anim/timeline.h"

using namespace rf;
using namespace rf::farm;

namespace {

using Clock = std::chrono::steady_clock;

std::string writeSceneFile() {
    const std::string dir = std::string(RAYFARM_TEST_OUT) + "/view_session";
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/farm_test.json";
    std::ofstream(path) << rf::testing::kFarmSceneJson;
    return path;
}

/// A camera the timeline never shows: the views must render through it, not the turntable's.
Camera freeCamera(const Scene& scene) {
    Camera c = scene.camera;
    c.eye = Vec3(2.5f, 1.5f, -4.f);
    return c;
}

/// still's pixels of `frame` through `camera` at spp (the scene posed by its timeline).
std::vector<uint8_t> stillThrough(const Camera& camera, int frame, int spp, int width, int height) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    anim::Timeline::fromScene(sceneLoaded).applyFrame(scene, frame);
    RenderSettings s = scene.settings;
    s.spp = spp;
    s.width = width;
    s.height = height;
    RayStats rays;
    return toRgb8(renderFrame(scene, {camera, s}, frame, 1, rays), s);
}

struct Picture {
    ViewPicture info;
    std::vector<uint8_t> rgb;
    Clock::time_point when;
};

/// A session on `ranks` loopback ranks (workers: runFarmWorker, as render's); `drive` runs on a
/// thread of its own with the inbox and what arrived so far, and sets the cancel flag when done.
struct Session {
    std::mutex m;
    std::vector<Picture> pictures;
    FarmOutcome outcome;
    std::vector<int> workerCodes;

    void run(int ranks, int spp, const std::function<void(Session&, ViewInbox&, std::atomic<bool>&)>& drive) {
        const std::string path = writeSceneFile();
        LoopbackHub hub(ranks);
        workerCodes.assign(size_t(ranks), -1);
        std::vector<std::thread> workers;
        for (int r = 1; r < ranks; ++r)
            workers.emplace_back([&, r] {
                LoopbackTransport t(hub, r);
                SharedScene s = shareScene(t, path, nullptr, nullptr);
                workerCodes[size_t(r)] = runFarmWorker(t, s, 0.0, 1, 20.0);
            });
        LoopbackTransport t(hub, 0);
        RenderJob job;
        SharedScene shared = shareScene(t, path, nullptr, [&](LoadedScene& scene, const FileBundle&) {
            job.settings = scene.scene.settings;
            job.settings.spp = spp;
            job.workerTimeout = 10.0;
            return encodeWorkerJob(job);
        });
        ViewInbox inbox;
        std::atomic<bool> cancel{false};
        FarmOptions opts;
        opts.views = &inbox;
        opts.cancel = &cancel;
        opts.threads = 1;
        opts.onFrame = [&](const FarmProgress& p) {
            ASSERT_TRUE(p.view && p.rgb);
            std::lock_guard<std::mutex> lock(m);
            pictures.push_back({*p.view, *p.rgb, Clock::now()});
            pictures.back().info.tiles = nullptr;
        };
        std::thread driver([&] { drive(*this, inbox, cancel); });
        outcome = runFarm(t, job, shared, {}, opts);
        driver.join();
        for (auto& w : workers) w.join();
    }
    /// Waits up to `seconds` for a complete picture of view `id`, pass `pass`.
    bool waitFor(uint64_t id, int pass, double seconds) {
        const auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end) {
            {
                std::lock_guard<std::mutex> lock(m);
                for (const Picture& p : pictures)
                    if (p.info.id == id && p.info.pass == pass && p.info.complete) return true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        return false;
    }
};

}  // namespace

class ViewSessionRanks : public ::testing::TestWithParam<int> {};

TEST_P(ViewSessionRanks, EveryPassIsTheStillThroughTheViewsCamera) {
    const int ranks = GetParam();
    const Camera cam = freeCamera(rf::testing::loadFarmScene().scene);
    Session s;
    s.run(ranks, 4, [&](Session& self, ViewInbox& inbox, std::atomic<bool>& cancel) {
        ViewOrder v;
        v.id = 7;
        v.frame = 3;
        v.camera = cam;
        v.passes = {{1, 20, 15}, {1, 40, 30}, {4, 40, 30}};  // a small moving pass, then refinement
        inbox.post(v);
        EXPECT_TRUE(self.waitFor(7, 2, 60.0));
        cancel = true;
    });
    EXPECT_EQ(s.outcome.end, FarmEnd::Cancelled);
    for (int r = 1; r < ranks; ++r) EXPECT_EQ(s.workerCodes[size_t(r)], 0) << "rank " << r << " was not told to stop";
    std::vector<const Picture*> whole;
    for (const Picture& p : s.pictures)
        if (p.info.complete) whole.push_back(&p);
    ASSERT_EQ(whole.size(), 3u);
    for (int pass = 0; pass < 3; ++pass) {
        const ViewPass& size = whole[size_t(pass)]->info.size;
        EXPECT_EQ(whole[size_t(pass)]->info.pass, pass);
        EXPECT_EQ(whole[size_t(pass)]->info.id, 7u);
        EXPECT_TRUE(whole[size_t(pass)]->rgb == stillThrough(cam, 3, size.spp, size.width, size.height))
            << "pass " << pass << " (" << size.width << "x" << size.height << ", " << size.spp << " spp) on " << ranks << " ranks";
    }
}

INSTANTIATE_TEST_SUITE_P(Farm, ViewSessionRanks, ::testing::Values(1, 2, 3));

TEST(ViewSession, TheTimelinesCameraWhenFollowingIt) {
    Session s;
    s.run(3, 1, [&](Session& self, ViewInbox& inbox, std::atomic<bool>& cancel) {
        ViewOrder v;
        v.id = 1;
        v.frame = 4;
        v.followTimeline = true;
        v.passes = {{1, 40, 30}};
        inbox.post(v);
        EXPECT_TRUE(self.waitFor(1, 0, 60.0));
        cancel = true;
    });
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    anim::Timeline::fromScene(sceneLoaded).applyFrame(scene, 4);
    ASSERT_FALSE(s.pictures.empty());
    EXPECT_TRUE(s.pictures.back().rgb == stillThrough(scene.camera, 4, 1, 40, 30));
}

TEST(ViewSession, ANewerViewCancelsTheWorkInFlightOnEveryRank) {
    // The first view takes seconds a tile (120x120 at 4096 spp: four 64-pixel tiles of about
    // 16 M samples each); the second is a quick 1 spp pass. It must not wait for the tiles the
    // ranks are rendering, and nothing of the first view may reach the caller after it.
    Clock::time_point posted;
    Session s;
    s.run(3, 4096, [&](Session& self, ViewInbox& inbox, std::atomic<bool>& cancel) {
        ViewOrder slow;
        slow.id = 1;
        slow.passes = {{4096, 120, 120}};
        slow.camera = rf::testing::loadFarmScene().scene.camera;
        inbox.post(slow);
        std::this_thread::sleep_for(std::chrono::milliseconds(300));  // its tiles are on the ranks
        ViewOrder quick = slow;
        quick.id = 2;
        quick.passes = {{1, 40, 30}};
        posted = Clock::now();
        inbox.post(quick);
        EXPECT_TRUE(self.waitFor(2, 0, 30.0));
        cancel = true;
    });
    Clock::time_point quickDone{};
    for (const Picture& p : s.pictures) {
        EXPECT_FALSE(p.info.id == 1 && p.info.complete) << "the replaced view was finished";
        EXPECT_FALSE(p.info.id == 1 && p.when > posted + std::chrono::milliseconds(50)) << "a picture of the replaced view came late";
        if (p.info.id == 2 && p.info.complete) quickDone = p.when;
    }
    ASSERT_NE(quickDone, Clock::time_point{});
    // A cancelled rank starts the new epoch between 16x16 sub-tiles (1 M samples), not after
    // its tile (about 6 s here when quiet).
    EXPECT_LT(std::chrono::duration<double>(quickDone - posted).count(), 3.0);
    for (int r = 1; r < 3; ++r) EXPECT_EQ(s.workerCodes[size_t(r)], 0) << "rank " << r;
}

TEST(ViewSession, ARenderEngineDropsEveryOtherEpochTheItemRenderingIncluded) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    RenderSettings s = scene.settings;
    RenderEngine engine(scene, tl, s, 1);
    // 120x120 at 1024 spp: 15 M samples, seconds on one thread; 16x16 sub-tiles of 0.26 M.
    ViewSpec slow;
    slow.epoch = 10;
    slow.spp = 1024;
    slow.width = 120;
    slow.height = 120;
    slow.camera = scene.camera;
    engine.setView(slow);
    engine.submit({0, {0, 0, 120, 120}, 10});
    engine.submit({0, {0, 0, 8, 8}, 10});
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the first is rendering
    EXPECT_EQ(engine.outstanding(), 2);
    ViewSpec quick = slow;
    quick.epoch = 11;
    quick.spp = 1;
    quick.width = s.width;
    quick.height = s.height;
    const auto t0 = Clock::now();
    engine.setView(quick);
    engine.submit({0, {0, 0, s.width, s.height}, 11});
    std::optional<TileResult> r = engine.takeResult(10.0);
    ASSERT_TRUE(r) << engine.error();
    EXPECT_EQ(r->item.epoch, 11u);  // neither item of epoch 10 gave a result
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 2.0);
    EXPECT_EQ(engine.outstanding(), 0);
    int applied = -1;
    Scene posed = scene;
    EXPECT_TRUE(r->rgb == RenderEngine::render(posed, tl, s, 1, {0, {0, 0, s.width, s.height}, 11}, applied, false, &quick).rgb);
}

TEST(ViewSession, JobFramesAreUntouchedByViews) {
    // Epoch 0 is the job's own frame: a view set on the engine changes nothing for it.
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    RenderEngine engine(scene, tl, scene.settings, 1);
    ViewSpec v;
    v.epoch = 5;
    v.spp = 4;
    v.width = 20;
    v.height = 15;
    v.camera = freeCamera(scene);
    engine.setView(v);
    engine.submit({2, {0, 0, scene.settings.width, scene.settings.height}});
    std::optional<TileResult> r = engine.takeResult(30.0);
    ASSERT_TRUE(r) << engine.error();
    EXPECT_TRUE(r->rgb == rf::testing::referenceFarmFrames().at(2));
}

namespace {
class KeepingSink : public FrameSink {
public:
    explicit KeepingSink(std::map<int, std::vector<uint8_t>>& out) : out_(out) {}
    void write(int frame, const std::vector<uint8_t>& rgb) override { out_[frame] = rgb; }
    void close() override {}

private:
    std::map<int, std::vector<uint8_t>>& out_;
};
}  // namespace

TEST(ViewSession, ALateResultOfAnEarlierRunIsDropped) {
    // A viewer renders a film, cancels it and renders again on the same workers (keepWorkers):
    // tiles the workers still held from the first run come back during the second, which must
    // not take them for its own ("returned work it was not given"). Here such a tile (the
    // epoch 0 every run had before runs got epochs of their own) waits in rank 0's mailbox.
    const std::string path = writeSceneFile();
    LoopbackHub hub(3);
    std::vector<int> codes(3, -1);
    std::vector<std::thread> workers;
    for (int r = 1; r < 3; ++r)
        workers.emplace_back([&, r] {
            LoopbackTransport t(hub, r);
            SharedScene s = shareScene(t, path, nullptr, nullptr);
            codes[size_t(r)] = runFarmWorker(t, s, 0.0, 1, 20.0);
        });
    LoopbackTransport t(hub, 0);
    RenderJob job;
    SharedScene shared = shareScene(t, path, nullptr, [&](LoadedScene& scene, const FileBundle&) {
        job.output = "memory.mp4";
        job.settings = scene.scene.settings;
        const anim::Timeline tl = anim::Timeline::fromScene(scene);
        job.timelineFrames = tl.frameCount();
        job.first = 0;
        job.last = tl.frameCount() - 1;
        job.mode = Mode::Pixel;
        job.tileSize = 16;
        return encodeWorkerJob(job);
    });
    TileResult late;
    late.item = {3, {0, 0, 16, 16}, 0};
    late.rgb.assign(late.layout.bytes(16 * 16), 0);
    LoopbackTransport(hub, 1).send(0, kTagResult, encodeTileResult(late));
    std::map<int, std::vector<uint8_t>> frames;
    FarmOptions opts;
    opts.quiet = true;
    FarmSinks sinks;
    sinks.video = std::make_unique<KeepingSink>(frames);
    FarmOutcome o;
    EXPECT_NO_THROW(o = runFarm(t, job, shared, std::move(sinks), opts));
    for (auto& w : workers) w.join();
    EXPECT_EQ(o.end, FarmEnd::Done) << o.error;
    EXPECT_EQ(frames, rf::testing::referenceFarmFrames());
    for (int r = 1; r < 3; ++r) EXPECT_EQ(codes[size_t(r)], 0) << "rank " << r;
}
