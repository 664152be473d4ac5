// The master and worker loops over the in-process transport, with real render engines: every
// mode and rank count gives the frames a single renderer gives, and a lost or failing worker
// ends the run with a message naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "farm/cluster/build_beats.h"
#include "tests/farm/farm_test_scene.h"
#include "farm/process/usage_error.h"
#include "engine/util/errors.h"
#include "farm/cluster/frame_assembler.h"
#include "farm/cluster/loopback_transport.h"
#include "farm/cluster/master.h"
#include "farm/cluster/messages.h"
#include "farm/cluster/scene_broadcast.h"
#include "anim/timeline.h"
#include "farm/cluster/worker.h"

using namespace rf;
using namespace rf::farm;

namespace {

struct FarmRun {
    MasterOutcome outcome;
    std::map<int, std::vector<uint8_t>> completed;  ///< as reported on completion, any order
    std::map<int, std::vector<uint8_t>> frames;
    std::vector<int> order;
};

// ranks: 1 = rank 0 alone (renders locally); more: workers 1..n-1 on threads.
FarmRun runFarm(int ranks, Mode mode, bool rank0Renders, int threads = 1) {
    LoopbackHub hub(ranks);
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    const RenderSettings settings = scene.settings;
    const anim::FrameRanges frames = anim::FrameRanges::span(0, tl.frameCount() - 1);

    std::vector<std::thread> workers;
    for (int r = 1; r < ranks; ++r)
        workers.emplace_back([&hub, r, threads] {
            LoopbackTransport t(hub, r);
            LoadedScene sLoaded = rf::testing::loadFarmScene();
            Scene& s = sLoaded.scene;
            const anim::Timeline wtl = anim::Timeline::fromScene(sLoaded);
            const RenderSettings st = s.settings;
            RenderEngine engine(std::move(s), wtl, st, threads);
            runWorker(t, engine);
        });

    LoopbackTransport t(hub, 0);
    const int renderers = rank0Renders ? ranks : ranks - 1;
    std::unique_ptr<Scheduler> sched = mode == Mode::Pixel
                                           ? makePixelScheduler(frames, settings.width, settings.height, 16, 3)
                                           : makeFrameScheduler(frames, settings.width, settings.height, 2 * renderers + 2);
    FrameAssembler assembler(settings.width, settings.height, frames, {});
    std::unique_ptr<RenderEngine> local;
    if (rank0Renders) local = std::make_unique<RenderEngine>(std::move(scene), tl, settings, threads);
    FarmRun run;
    MasterConfig cfg;
    cfg.quiet = true;
    cfg.workerTimeout = 20.0;
    Master master(t, *sched, assembler, local.get(),
                  [&](ReadyFrame& f) {
                      run.order.push_back(f.frame);
                      run.frames[f.frame] = f.rgb;
                  },
                  cfg);
    master.onFrameComplete([&](int f, const std::vector<uint8_t>& rgb) {
        EXPECT_EQ(run.completed.count(f), 0u) << "frame " << f << " completed twice";
        run.completed[f] = rgb;
    });
    run.outcome = master.run();
    master.stopWorkers();
    for (auto& w : workers) w.join();
    return run;
}

}  // namespace

TEST(Master, TestSceneIsAnAnimatedTimeline) {
    const anim::Timeline tl = anim::Timeline::fromScene(rf::testing::loadFarmScene());
    ASSERT_EQ(tl.frameCount(), 6);
    const auto ref = rf::testing::referenceFarmFrames();
    EXPECT_NE(ref.at(0), ref.at(3));  // the camera moved: frames differ, so mix-ups would show
}

struct FarmCase {
    int ranks;
    Mode mode;
    bool rank0Renders;
    int threads;
};

void PrintTo(const FarmCase& c, std::ostream* os) {
    *os << c.ranks << " ranks, " << (c.mode == Mode::Pixel ? "pixel" : "frame") << (c.rank0Renders ? ", rank 0 renders" : "")
        << ", " << c.threads << " threads";
}

class MasterModes : public ::testing::TestWithParam<FarmCase> {};

TEST_P(MasterModes, FramesAreBitIdenticalToOneRendererAndInOrder) {
    const FarmCase c = GetParam();
    const FarmRun run = runFarm(c.ranks, c.mode, c.rank0Renders, c.threads);
    ASSERT_EQ(run.outcome.end, RunEnd::Done) << run.outcome.message;
    const auto ref = rf::testing::referenceFarmFrames();
    ASSERT_EQ(run.frames.size(), ref.size());
    for (size_t i = 0; i < run.order.size(); ++i) EXPECT_EQ(run.order[i], int(i));
    for (const auto& [f, rgb] : ref) EXPECT_TRUE(run.frames.at(f) == rgb) << "frame " << f << " differs";
    EXPECT_EQ(run.completed, run.frames);  // the PNG path sees the same pixels as the video path
    // Every rendering rank did some of the work.
    for (int r = c.rank0Renders ? 0 : 1; r < c.ranks; ++r)
        EXPECT_GT(run.outcome.perRank[size_t(r)].frames + run.outcome.perRank[size_t(r)].tiles, 0) << "rank " << r;
    EXPECT_GT(run.outcome.rays.primary, 0u);
}

INSTANTIATE_TEST_SUITE_P(Farm, MasterModes,
                         ::testing::Values(FarmCase{1, Mode::Frame, true, 2}, FarmCase{1, Mode::Pixel, true, 2},
                                           FarmCase{2, Mode::Frame, true, 1}, FarmCase{2, Mode::Pixel, true, 1},
                                           FarmCase{3, Mode::Frame, false, 1}, FarmCase{3, Mode::Pixel, false, 2}));

TEST(Master, SilentWorkerStopsTheRunNamingRankAndFrame) {
    // Rank 2 takes work and never answers (a stopped process); rank 1 works normally.
    LoopbackHub hub(3);
    std::thread worker([&hub] {
        LoopbackTransport t(hub, 1);
        LoadedScene sLoaded = rf::testing::loadFarmScene();
        Scene& s = sLoaded.scene;
        const anim::Timeline tl = anim::Timeline::fromScene(sLoaded);
        const RenderSettings st = s.settings;
        RenderEngine engine(std::move(s), tl, st, 1);
        runWorker(t, engine);
    });
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    LoopbackTransport t(hub, 0);
    auto sched = makeFrameScheduler({0, 1, 2, 3, 4, 5}, scene.settings.width, scene.settings.height, 8);
    FrameAssembler assembler(scene.settings.width, scene.settings.height, {0, 1, 2, 3, 4, 5}, {});
    MasterConfig cfg;
    cfg.quiet = true;
    cfg.workerTimeout = 0.5;
    Master master(t, *sched, assembler, nullptr, [](ReadyFrame&) {}, cfg);
    const auto t0 = std::chrono::steady_clock::now();
    const MasterOutcome o = master.run();
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    master.stopWorkers();
    worker.join();
    EXPECT_EQ(o.end, RunEnd::WorkerLost);
    EXPECT_NE(o.message.find("rank 2 stopped answering"), std::string::npos) << o.message;
    EXPECT_NE(o.message.find("frame"), std::string::npos) << o.message;
    EXPECT_LT(took, 5.0);  // a bound on detection, not a speed measurement
}

// Issue 45: with requeueLost the silent rank's frames go to the rank still working, and the
// film completes, every frame as one renderer makes it, the lost rank listed in the outcome.
// In pixel mode its tiles go out again the same way.
TEST(Master, ASilentWorkersWorkGoesToTheOthersAndTheFilmCompletes) {
    const auto reference = rf::testing::referenceFarmFrames();
    for (const Mode mode : {Mode::Frame, Mode::Pixel}) {
        LoopbackHub hub(3);  // rank 2 takes work and never answers
        std::thread worker([&hub] {
            LoopbackTransport t(hub, 1);
            LoadedScene sLoaded = rf::testing::loadFarmScene();
            Scene& s = sLoaded.scene;
            const anim::Timeline tl = anim::Timeline::fromScene(sLoaded);
            const RenderSettings st = s.settings;
            RenderEngine engine(std::move(s), tl, st, 1);
            runWorker(t, engine);
        });
        LoadedScene sceneLoaded = rf::testing::loadFarmScene();
        Scene& scene = sceneLoaded.scene;
        const int w = scene.settings.width, h = scene.settings.height;
        LoopbackTransport t(hub, 0);
        const anim::FrameRanges all = anim::FrameRanges::span(0, int(reference.size()) - 1);
        auto sched = mode == Mode::Frame ? makeFrameScheduler(all, w, h, 8) : makePixelScheduler(all, w, h, 16, 4);
        FrameAssembler assembler(w, h, all, {});
        MasterConfig cfg;
        cfg.quiet = true;
        cfg.workerTimeout = 2.0;  // a live rank late by 0.5 s on a loaded machine is no loss
        cfg.requeueLost = true;
        std::vector<std::string> notes;
        cfg.log = [&notes](const std::string& line) { notes.push_back(line); };
        std::map<int, std::vector<uint8_t>> frames;
        Master master(t, *sched, assembler, nullptr, [&](ReadyFrame& rf) { frames[rf.frame] = rf.rgb; }, cfg);
        const MasterOutcome o = master.run();
        master.stopWorkers();
        worker.join();
        const char* m = mode == Mode::Frame ? "frame mode" : "pixel mode";
        ASSERT_EQ(o.end, RunEnd::Done) << m << ": " << o.message;
        ASSERT_EQ(o.lost.size(), 1u) << m;
        EXPECT_EQ(o.lost[0].rank, 2) << m;
        EXPECT_NE(o.lost[0].requeued.find("frame"), std::string::npos) << m << ": " << o.lost[0].requeued;
        ASSERT_EQ(notes.size(), 1u) << m;
        EXPECT_NE(notes[0].find("rank 2 stopped answering"), std::string::npos) << notes[0];
        ASSERT_EQ(frames.size(), reference.size()) << m;
        for (const auto& [f, rgb] : reference) EXPECT_TRUE(frames.at(f) == rgb) << m << ": frame " << f << " differs from one renderer's";
    }
}

// Issue 45 #3: a worker given up on that speaks again (a process continued after SIGSTOP) has
// what it sends ignored, is said to have come back, and is told to leave (kStopAfterLossExit);
// the film is one renderer's, frame for frame.
TEST(Master, AWorkerThatComesBackAfterItWasGivenUpOnIsIgnoredAndToldToLeave) {
    const auto reference = rf::testing::referenceFarmFrames();
    LoopbackHub hub(3);
    auto worker = [&hub](int rank, double startAfter, int* code) {
        return std::thread([&hub, rank, startAfter, code] {
            std::this_thread::sleep_for(std::chrono::duration<double>(startAfter));  // stopped, then continued
            LoopbackTransport t(hub, rank);
            LoadedScene sLoaded = rf::testing::loadFarmScene();
            Scene& s = sLoaded.scene;
            const anim::Timeline tl = anim::Timeline::fromScene(sLoaded);
            const RenderSettings st = s.settings;
            RenderEngine engine(std::move(s), tl, st, 1);
            *code = runWorker(t, engine);
        });
    };
    int code1 = -1, code2 = -1;
    std::thread w1 = worker(1, 0.0, &code1);
    std::thread w2 = worker(2, 3.0, &code2);  // silent past the 2 s timeout, then back
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const int w = scene.settings.width, h = scene.settings.height;
    LoopbackTransport t(hub, 0);
    const anim::FrameRanges all = anim::FrameRanges::span(0, int(reference.size()) - 1);
    auto sched = makeFrameScheduler(all, w, h, 8);
    FrameAssembler assembler(w, h, all, {});
    MasterConfig cfg;
    cfg.quiet = true;
    cfg.workerTimeout = 2.0;  // a live rank late by 0.5 s on a loaded machine is no loss
    cfg.requeueLost = true;
    std::vector<std::string> notes;
    cfg.log = [&notes](const std::string& line) { notes.push_back(line); };
    std::map<int, std::vector<uint8_t>> frames;
    Master master(t, *sched, assembler, nullptr, [&](ReadyFrame& rf) { frames[rf.frame] = rf.rgb; }, cfg);
    const MasterOutcome o = master.run();
    // Rank 2 comes back while the film may still render: rank 0 hears it there, or here.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    auto heard = [&notes] {
        return std::any_of(notes.begin(), notes.end(), [](const std::string& n) { return n.find("answered again") != std::string::npos; });
    };
    master.idle([&] { return heard() || std::chrono::steady_clock::now() > until; });
    master.stopWorkers();
    w1.join();
    w2.join();
    ASSERT_EQ(o.end, RunEnd::Done) << o.message;
    ASSERT_EQ(o.lost.size(), 1u);
    EXPECT_EQ(o.lost[0].rank, 2);
    EXPECT_TRUE(std::any_of(notes.begin(), notes.end(), [](const std::string& n) { return n.find("rank 2 answered again") != std::string::npos; }))
        << "no note that rank 2 came back";
    EXPECT_EQ(code2, kStopAfterLossExit) << "rank 2 was not told to leave as a lost rank";
    EXPECT_EQ(code1, kStopAfterLossExit) << "after a loss every rank leaves without MPI_Finalize";
    ASSERT_EQ(frames.size(), reference.size());
    for (const auto& [f, rgb] : reference) EXPECT_TRUE(frames.at(f) == rgb) << "frame " << f << " differs from one renderer's";
}

// Issue 45: no rendering rank left, or one frame held by maxFrameFailures ranks when each was
// lost, ends the run naming why.
TEST(Master, TheRunStopsWhenNoWorkerIsLeftOrAFrameTookDownTooMany) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const int w = scene.settings.width, h = scene.settings.height;
    for (const int failures : {3, 1}) {
        LoopbackHub hub(3);  // ranks 1 and 2 take work and never answer
        LoopbackTransport t(hub, 0);
        auto sched = makeFrameScheduler({0, 1, 2, 3, 4, 5}, w, h, 8);
        FrameAssembler assembler(w, h, {0, 1, 2, 3, 4, 5}, {});
        MasterConfig cfg;
        cfg.quiet = true;
        cfg.workerTimeout = 0.5;
        cfg.requeueLost = true;
        cfg.maxFrameFailures = failures;
        cfg.log = [](const std::string&) {};
        Master master(t, *sched, assembler, nullptr, [](ReadyFrame&) {}, cfg);
        const MasterOutcome o = master.run();
        EXPECT_EQ(o.end, RunEnd::WorkerLost);
        if (failures == 1) {
            EXPECT_EQ(o.lost.size(), 1u);
            EXPECT_NE(o.message.find("frame 0 was being rendered by each of the 1 ranks"), std::string::npos) << o.message;
        } else {
            EXPECT_EQ(o.lost.size(), 2u);
            EXPECT_NE(o.message.find("no worker is left"), std::string::npos) << o.message;
        }
    }
}

// Issue 30 #4: rank 0 starts its clock once its own build is done; a worker still building
// (a huge scene or environment, a slower host) was declared dead. Its build beats keep it alive
// past the timeout; a worker that goes silent while building is still found, and named so.
TEST(Master, AWorkerBuildingItsSceneIsAliveAndNamedSoIfItGoesSilent) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const int w = scene.settings.width, h = scene.settings.height;
    MasterConfig cfg;
    cfg.quiet = true;
    cfg.workerTimeout = 0.5;
    {
        LoopbackHub hub(2);
        std::thread worker([&hub] {
            LoopbackTransport t(hub, 1);
            LoadedScene sLoaded = rf::testing::loadFarmScene();
            Scene& s = sLoaded.scene;
            {
                BuildBeats beats(t);
                std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // three timeouts of building
            }
            const anim::Timeline tl = anim::Timeline::fromScene(sLoaded);
            const RenderSettings st = s.settings;
            RenderEngine engine(std::move(s), tl, st, 1);
            runWorker(t, engine);
        });
        LoopbackTransport t(hub, 0);
        auto sched = makeFrameScheduler({0, 1}, w, h, 4);
        FrameAssembler assembler(w, h, {0, 1}, {});
        Master master(t, *sched, assembler, nullptr, [](ReadyFrame&) {}, cfg);
        const MasterOutcome o = master.run();
        master.stopWorkers();
        worker.join();
        EXPECT_EQ(o.end, RunEnd::Done) << o.message;
    }
    {
        LoopbackHub hub(2);
        std::atomic<bool> over{false};
        std::thread worker([&hub, &over] {
            LoopbackTransport t(hub, 1);
            {
                BuildBeats beats(t);
                std::this_thread::sleep_for(std::chrono::milliseconds(300));
            }
            while (!over) std::this_thread::sleep_for(std::chrono::milliseconds(10));  // then silent: a hung host
        });
        LoopbackTransport t(hub, 0);
        auto sched = makeFrameScheduler({0, 1}, w, h, 4);
        FrameAssembler assembler(w, h, {0, 1}, {});
        Master master(t, *sched, assembler, nullptr, [](ReadyFrame&) {}, cfg);
        const MasterOutcome o = master.run();
        over = true;
        worker.join();
        EXPECT_EQ(o.end, RunEnd::WorkerLost);
        EXPECT_NE(o.message.find("rank 1 stopped answering (silent for"), std::string::npos) << o.message;
        EXPECT_NE(o.message.find("while building its scene"), std::string::npos) << o.message;
    }
}

TEST(Master, WorkerErrorEndsTheRunNamingTheRank) {
    LoopbackHub hub(2);
    LoopbackTransport t(hub, 0);
    LoopbackTransport w(hub, 1);
    reportWorkerError(w, "frame 3: out of memory");
    auto sched = makeFrameScheduler({0, 1, 2, 3}, 8, 8, 4);
    FrameAssembler assembler(8, 8, {0, 1, 2, 3}, {});
    MasterConfig cfg;
    cfg.quiet = true;
    Master master(t, *sched, assembler, nullptr, [](ReadyFrame&) {}, cfg);
    const MasterOutcome o = master.run();
    EXPECT_EQ(o.end, RunEnd::Failed);
    EXPECT_EQ(o.message, "rank 1: frame 3: out of memory");
}

TEST(SceneBroadcast, WorkersLoadTheSceneFromRankZerosBytesOnly) {
    // Rank 0 reads a real file; after the broadcast the file is gone, so the others can only
    // have used the bundle. All three must then render the same frame.
    const std::string dir = std::string(RAYFARM_TEST_OUT) + "/farm_broadcast";
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/scene.json";
    { std::ofstream(path) << rf::testing::kFarmSceneJson; }
    LoopbackHub hub(3);
    std::vector<std::vector<uint8_t>> frames(3);
    std::vector<std::string> jobs(3);
    std::vector<std::thread> ranks;
    for (int r = 0; r < 3; ++r)
        ranks.emplace_back([&, r] {
            LoopbackTransport t(hub, r);
            SharedScene s = shareScene(t, path, nullptr, [&](LoadedScene&, const FileBundle&) {
                std::filesystem::remove(path);
                return std::string("job-bytes");
            });
            jobs[size_t(r)] = s.job;
            const anim::Timeline tl = anim::Timeline::fromScene(s);
            int applied = -1;
            const RenderSettings st = s.scene.settings;
            frames[size_t(r)] = RenderEngine::render(s.scene, tl, st, 1, {4, {0, 0, st.width, st.height}}, applied).rgb;
        });
    for (auto& th : ranks) th.join();
    EXPECT_FALSE(std::filesystem::exists(path));
    for (int r = 0; r < 3; ++r) {
        EXPECT_EQ(jobs[size_t(r)], "job-bytes");
        EXPECT_TRUE(frames[size_t(r)] == frames[0]) << "rank " << r;
    }
    EXPECT_FALSE(frames[0].empty());
}

TEST(SceneBroadcast, BadSceneOnRankZeroTellsTheOthers) {
    LoopbackHub hub(2);
    int workerCode = 0;
    std::thread worker([&] {
        LoopbackTransport t(hub, 1);
        try {
            shareScene(t, "/nonexistent/scene.json", nullptr, nullptr);
        } catch (const PeerFailed& e) {
            workerCode = e.code();
        }
    });
    LoopbackTransport t(hub, 0);
    EXPECT_THROW(shareScene(t, "/nonexistent/scene.json", nullptr, nullptr), InputError);
    worker.join();
    EXPECT_EQ(workerCode, 2);
}

TEST(SceneBroadcast, GltfModelLoadsFromTheBundleAsFromDisk) {
    // A real binary glTF through the path the workers take: disk on rank 0, bundle elsewhere.
    const std::string glb = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    DiskFileSource disk;
    LoadedScene aLoaded = loadScene(glb, disk);
    Scene& a = aLoaded.scene;
    BundleFileSource mem(FileBundle::deserialize(disk.bundle().serialize()));
    LoadedScene bLoaded = loadScene(glb, mem);
    Scene& b = bLoaded.scene;
    EXPECT_EQ(a.geometry.triangleCount(), b.geometry.triangleCount());
    EXPECT_GT(a.geometry.triangleCount(), 100000u);
    const anim::Timeline ta = anim::Timeline::fromScene(aLoaded), tb = anim::Timeline::fromScene(bLoaded);
    EXPECT_EQ(ta.frameCount(), tb.frameCount());
    RenderSettings s = a.settings;
    s.width = 32;
    s.height = 24;
    int fa = -1, fb = -1;
    EXPECT_TRUE(RenderEngine::render(a, ta, s, 1, {5, {0, 0, 32, 24}}, fa).rgb ==
                RenderEngine::render(b, tb, s, 1, {5, {0, 0, 32, 24}}, fb).rgb);
}

TEST(SceneBroadcast, WorkersBuildFromTheFilesWhileRankZeroBuildsItsOwn) {
    // A glTF under an .exr environment: rank 0 sends the files as soon as its loader has read
    // them, before it builds meshes, BVH and environment maps. Each rank's loader calls its
    // options' inputsRead at that point; rank 0's waits there for the worker's, which can only
    // come if the files went out before rank 0's build. makeJob deletes the files, so the worker
    // can only have used the bytes it was sent.
    const std::string dir = std::string(RAYFARM_TEST_OUT) + "/farm_broadcast_early";
    std::filesystem::create_directories(dir);
    const std::string glb = dir + "/engine.glb", exr = dir + "/studio.exr";
    std::filesystem::copy_file("/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", glb,
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy_file(RAYFARM_SOURCE_DIR "/scenes/environments/studio.exr", exr,
                               std::filesystem::copy_options::overwrite_existing);
    std::atomic<bool> workerRead{false};
    bool rankZeroSawWorkerRead = false;
    LoopbackHub hub(2);
    std::vector<std::vector<uint8_t>> frames(2);
    std::vector<std::thread> ranks;
    for (int r = 0; r < 2; ++r)
        ranks.emplace_back([&, r] {
            SceneOptions options;
            options.environment = EnvironmentSpec{exr, 30.f, 1.f};
            if (r == 0)
                options.inputsRead = [&] {
                    for (int i = 0; i < 2000 && !workerRead; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
                    rankZeroSawWorkerRead = workerRead;
                };
            else
                options.inputsRead = [&] { workerRead = true; };
            LoopbackTransport t(hub, r);
            SharedScene s = shareScene(
                t, glb, nullptr,
                [&](LoadedScene&, const FileBundle& files) {
                    EXPECT_EQ(files.files.size(), 2u);
                    std::filesystem::remove(glb);
                    std::filesystem::remove(exr);
                    return std::string("job");
                },
                options);
            EXPECT_EQ(s.job, "job");
            RenderSettings st = s.scene.settings;
            st.width = 48;
            st.height = 27;
            int applied = -1;
            frames[size_t(r)] = RenderEngine::render(s.scene, anim::Timeline::fromScene(s), st, 1, {7, {0, 0, 48, 27}}, applied).rgb;
        });
    for (auto& th : ranks) th.join();
    EXPECT_TRUE(rankZeroSawWorkerRead) << "the files did not reach the worker before rank 0 built its scene";
    EXPECT_FALSE(frames[0].empty());
    EXPECT_TRUE(frames[1] == frames[0]);
}

TEST(SceneBroadcast, AFailureAfterTheFilesWentOutStopsTheWorkers) {
    // The files have gone out; the job then fails (a usage error): the worker, done loading,
    // learns it from the second broadcast and stops with rank 0's exit code.
    const std::string dir = std::string(RAYFARM_TEST_OUT) + "/farm_broadcast_late_failure";
    std::filesystem::create_directories(dir);
    const std::string glb = dir + "/engine.glb";
    std::filesystem::copy_file("/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", glb,
                               std::filesystem::copy_options::overwrite_existing);
    LoopbackHub hub(2);
    int workerCode = 0;
    std::thread worker([&] {
        LoopbackTransport t(hub, 1);
        try {
            shareScene(t, glb, nullptr, nullptr);
        } catch (const PeerFailed& e) {
            workerCode = e.code();
        }
    });
    LoopbackTransport t(hub, 0);
    EXPECT_THROW(shareScene(t, glb, nullptr, [](LoadedScene&, const FileBundle&) -> std::string { throw UsageError("--frames 9:3: empty"); }),
                 UsageError);
    worker.join();
    EXPECT_EQ(workerCode, 2);
}

// Issue 32: small tiles fill a rank's threads only if the rank holds enough of them. A rank
// whose heartbeat says it has T render threads is given 2 × T × 4 sub-tiles' worth of items
// (RenderEngine renders them together); one that has not said holds the configured credits.
TEST(Master, ARankWithMoreThreadsHoldsMoreSmallTiles) {
    for (int threads : {0, 2, 3}) {
        LoopbackHub hub(2);
        std::atomic<int> received{0};
        std::atomic<bool> done{false};
        std::thread worker([&] {
            LoopbackTransport t(hub, 1);
            Heartbeat h;
            h.threads = threads;
            while (!done) {
                t.send(0, kTagHeartbeat, encodeHeartbeat(h));  // alive, and never returns a tile
                Message m;
                while (t.poll(m))
                    if (m.tag == kTagWork) ++received;
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
        });
        LoopbackTransport t(hub, 0);
        auto sched = makePixelScheduler(anim::FrameRanges::span(0, 9), 40, 30, 16, 10);  // 60 tiles of one sub-tile
        FrameAssembler assembler(40, 30, anim::FrameRanges::span(0, 9), {});
        MasterConfig cfg;
        cfg.quiet = true;
        cfg.credits = 2;
        cfg.subTilesPerItem = 1;
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(400);
        cfg.between = [&] { return std::chrono::steady_clock::now() > until; };
        Master master(t, *sched, assembler, nullptr, [](ReadyFrame&) {}, cfg);
        EXPECT_EQ(master.run().end, RunEnd::Yielded);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        done = true;
        worker.join();
        EXPECT_EQ(received.load(), threads == 0 ? 2 : 2 * threads * 4) << threads << " threads";
    }
}
