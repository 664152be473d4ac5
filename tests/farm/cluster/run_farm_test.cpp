// The farm entry point over the in-process transport, as a viewer would call it: the scene is
// shared by broadcast, workers serve through runFarmWorker, frames reach the caller's sink and
// progress callback in order and bit-identical to one renderer; a cancel flag stops the run with
// the finished frames kept.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include <unistd.h>

#include "tests/farm/farm_test_scene.h"
#include "farm/cluster/loopback_transport.h"
#include "farm/cluster/render_engine.h"
#include "farm/output/mp4_sink.h"
#include "farm/output/png_encoder.h"
#include "farm/cluster/run_farm.h"
#include "anim/timeline.h"

using namespace rf;
using namespace rf::farm;

namespace {

/// Keeps what it is given, in arrival order, in storage the test owns (runFarm owns the sink).
class CollectingSink : public FrameSink {
public:
    explicit CollectingSink(std::vector<std::pair<int, std::vector<uint8_t>>>& out) : out_(out) {}
    void write(int frame, const std::vector<uint8_t>& rgb) override { out_.emplace_back(frame, rgb); }
    void close() override {}

private:
    std::vector<std::pair<int, std::vector<uint8_t>>>& out_;
};

std::string writeSceneFile() {
    const std::string dir = std::string(RAYFARM_TEST_OUT) + "/run_farm";
    std::filesystem::create_directories(dir);
    // CTest runs each case as its own process, in parallel: a path shared between them is
    // rewritten under a reader. Each process writes its own copy, whole, then renames it.
    const std::string path = dir + "/farm_test." + std::to_string(::getpid()) + ".json";
    const std::string part = path + ".part";
    std::ofstream(part) << rf::testing::kFarmSceneJson;
    std::filesystem::rename(part, path);
    return path;
}

/// The job rank 0 decides for the test scene: every frame, the given mode, no files.
RenderJob jobFor(const LoadedScene& loaded, Mode mode) {
    RenderJob job;
    job.output = "memory.mp4";
    job.settings = loaded.scene.settings;
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    job.timelineFrames = tl.frameCount();
    job.first = 0;
    job.last = tl.frameCount() - 1;
    job.mode = mode;
    job.tileSize = 16;
    return job;
}

struct LoopbackRun {
    FarmOutcome outcome;
    std::vector<std::pair<int, std::vector<uint8_t>>> video, frames;
    std::vector<FarmProgress> progress;  ///< rgb pointers cleared: they are valid only during the call
};

/// ranks loopback ranks; rank 0 calls runFarm, the others runFarmWorker. cancelAfter > 0 sets
/// the cancel flag from the progress callback once that many frames went out.
LoopbackRun runLoopbackFarm(int ranks, Mode mode, int cancelAfter = 0) {
    const std::string path = writeSceneFile();
    LoopbackHub hub(ranks);
    std::vector<std::thread> workers;
    std::vector<int> workerCodes(size_t(ranks), -1);
    for (int r = 1; r < ranks; ++r)
        workers.emplace_back([&, r] {
            LoopbackTransport t(hub, r);
            SharedScene s = shareScene(t, path, nullptr, nullptr);
            workerCodes[size_t(r)] = runFarmWorker(t, s, 0.0, 1, 20.0);
        });
    LoopbackTransport t(hub, 0);
    RenderJob job;
    SharedScene shared = shareScene(t, path, nullptr, [&](LoadedScene& scene, const FileBundle&) {
        job = jobFor(scene, mode);
        return encodeWorkerJob(job);
    });
    LoopbackRun run;
    std::atomic<bool> cancel{false};
    FarmSinks sinks;
    sinks.video = std::make_unique<CollectingSink>(run.video);
    sinks.frames = std::make_unique<CollectingSink>(run.frames);
    FarmOptions opts;
    opts.quiet = true;
    opts.cancel = &cancel;
    opts.onFrame = [&](const FarmProgress& p) {
        EXPECT_TRUE(p.rgb && p.rgb->size() == size_t(job.settings.width * job.settings.height * 3));
        FarmProgress copy = p;
        copy.rgb = nullptr;
        run.progress.push_back(copy);
        if (cancelAfter > 0 && p.framesDone >= cancelAfter) cancel = true;
    };
    run.outcome = runFarm(t, job, shared, std::move(sinks), opts);
    for (auto& w : workers) w.join();
    for (int r = 1; r < ranks; ++r) EXPECT_EQ(workerCodes[size_t(r)], 0) << "rank " << r;
    return run;
}

}  // namespace

class RunFarmModes : public ::testing::TestWithParam<std::pair<int, Mode>> {};

TEST_P(RunFarmModes, FramesReachTheSinksInOrderAndMatchOneRenderer) {
    const auto [ranks, mode] = GetParam();
    const LoopbackRun run = runLoopbackFarm(ranks, mode);
    ASSERT_EQ(run.outcome.end, FarmEnd::Done) << run.outcome.error;
    const auto ref = rf::testing::referenceFarmFrames();
    ASSERT_EQ(run.video.size(), ref.size());
    ASSERT_EQ(run.progress.size(), ref.size());
    for (size_t i = 0; i < run.video.size(); ++i) {
        EXPECT_EQ(run.video[i].first, int(i));
        EXPECT_TRUE(run.video[i].second == ref.at(int(i))) << "frame " << i << " differs from one renderer";
        EXPECT_EQ(run.progress[i].frame, int(i));
        EXPECT_EQ(run.progress[i].framesDone, int(i) + 1);
        EXPECT_EQ(run.progress[i].framesTotal, int(ref.size()));
        EXPECT_FALSE(run.progress[i].kept);
    }
    std::map<int, std::vector<uint8_t>> frames(run.frames.begin(), run.frames.end());
    EXPECT_EQ(frames, ref);  // the frames sink saw every frame once, with the same pixels
    EXPECT_EQ(run.outcome.stats.frames, int(ref.size()));
    EXPECT_EQ(run.outcome.stats.ranks, ranks);
    EXPECT_GT(run.outcome.stats.rays.primary, 0u);
    EXPECT_EQ(run.outcome.videoHolds, "the video memory.mp4 holds frames 0–5 of 0–5");
}

INSTANTIATE_TEST_SUITE_P(Farm, RunFarmModes,
                         ::testing::Values(std::pair{1, Mode::Frame}, std::pair{2, Mode::Pixel}, std::pair{3, Mode::Frame}));

TEST(RunFarm, CancelFlagStopsTheRunKeepingTheFramesDone) {
    const LoopbackRun run = runLoopbackFarm(1, Mode::Frame, 2);
    EXPECT_EQ(run.outcome.end, FarmEnd::Cancelled);
    EXPECT_EQ(run.outcome.signal, 0);
    EXPECT_FALSE(run.outcome.abortRanks);
    // The flag is read between scheduling steps: frames already complete may still go out.
    ASSERT_GE(run.video.size(), 2u);
    EXPECT_LT(run.video.size(), 6u);
    EXPECT_EQ(run.outcome.stats.frames, int(run.video.size()));
    const auto ref = rf::testing::referenceFarmFrames();
    for (const auto& [f, rgb] : run.video) EXPECT_TRUE(rgb == ref.at(f)) << "frame " << f;
    EXPECT_EQ(run.outcome.videoHolds,
              "the video memory.mp4 holds frames 0–" + std::to_string(run.video.size() - 1) + " of 0–5");
}

TEST(RunFarm, MissingVideoSinkIsRefused) {
    LoopbackHub hub(1);
    LoopbackTransport t(hub, 0);
    SharedScene shared;
    shared.loaded() = rf::testing::loadFarmScene();
    const RenderJob job = jobFor(shared, Mode::Frame);
    EXPECT_THROW(runFarm(t, job, shared, FarmSinks{}, FarmOptions{}), std::invalid_argument);
}

namespace {

/// A sink whose write of frame `failAt` (or, failAt < 0, whose close) throws, as a full disk
/// does; it keeps nothing.
class FailingSink : public FrameSink {
public:
    explicit FailingSink(int failAt) : failAt_(failAt) {}
    void write(int frame, const std::vector<uint8_t>&) override {
        if (frame == failAt_) throw std::runtime_error("out/frame.png: cannot write: No space left on device");
    }
    void close() override {
        if (failAt_ < 0) throw std::runtime_error("out/frame.png: cannot write: No space left on device");
    }

private:
    int failAt_;
};

/// Two loopback ranks with the given sinks; returns what runFarm threw ("" if it returned).
std::string failedRunMessage(std::unique_ptr<FrameSink> video, std::unique_ptr<FrameSink> frames) {
    const std::string path = writeSceneFile();
    LoopbackHub hub(2);
    std::thread worker([&] {
        LoopbackTransport t(hub, 1);
        SharedScene s = shareScene(t, path, nullptr, nullptr);
        runFarmWorker(t, s, 0.0, 1, 20.0);
    });
    LoopbackTransport t(hub, 0);
    RenderJob job;
    SharedScene shared = shareScene(t, path, nullptr, [&](LoadedScene& scene, const FileBundle&) {
        job = jobFor(scene, Mode::Frame);
        return encodeWorkerJob(job);
    });
    FarmSinks sinks;
    sinks.video = std::move(video);
    sinks.frames = std::move(frames);
    FarmOptions opts;
    opts.quiet = true;
    std::string what;
    try {
        runFarm(t, job, shared, std::move(sinks), opts);
    } catch (const std::exception& e) {
        what = e.what();
    }
    worker.join();
    return what;
}

}  // namespace

// A failed frame write reached the user in two forms, depending on which thread saw it first
// (caught inside the master's loop, or thrown from the sinks' close): now one, whatever the path.
TEST(RunFarm, AFailedWriteGivesOneMessageWhicheverPathItTakes) {
    std::vector<std::pair<int, std::vector<uint8_t>>> kept;
    const std::string prefix = "out/frame.png: cannot write: No space left on device; the video memory.mp4 holds ";
    const std::string atWrite = failedRunMessage(std::make_unique<CollectingSink>(kept), std::make_unique<FailingSink>(2));
    const std::string atClose = failedRunMessage(std::make_unique<CollectingSink>(kept), std::make_unique<FailingSink>(-1));
    const std::string inVideo = failedRunMessage(std::make_unique<FailingSink>(3), std::make_unique<CollectingSink>(kept));
    for (const std::string& m : {atWrite, atClose, inVideo}) {
        EXPECT_EQ(m.rfind(prefix, 0), 0u) << m;
        EXPECT_NE(m.find(" of 0–5"), std::string::npos) << m;
        EXPECT_EQ(m.find(prefix, 1), std::string::npos) << "said twice: " << m;
    }
    EXPECT_EQ(atClose, prefix + "frames 0–5 of 0–5");  // every frame reached the video before the close failed
}

namespace {

/// The PNG frames as a rank sent them (writePng), decoded back for comparison.
class PngCollectingSink : public FrameSink {
public:
    PngCollectingSink(std::map<int, std::string>& out, int& rawWrites) : out_(out), raw_(rawWrites) {}
    void write(int, const std::vector<uint8_t>&) override { ++raw_; }
    void writePng(int frame, const std::string& png, const std::string&) override { out_[frame] = png; }
    void close() override {}

private:
    std::map<int, std::string>& out_;
    int& raw_;
};

struct ChunkedRun {
    FarmOutcome outcome;
    std::string video;                 ///< the file's bytes
    std::map<int, std::string> pngs;   ///< PNG frames that reached rank 0 as PNGs
    int rawFrameWrites = 0;            ///< frames that reached the PNG sink as pixels
};

/// ranks loopback ranks render the test scene to a real MP4 in chunks of 2 frames, in `mode`,
/// the chunks encoded on the rendering ranks (onRanks: frame mode's rank renders its chunk's
/// frames, the film's last ones shared, pixel mode's assembles it from tiles) or all on rank 0.
ChunkedRun runChunkedFarm(int ranks, Mode mode, bool onRanks = true) {
    const std::string path = writeSceneFile();
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/run_farm/chunked_" + std::to_string(::getpid()) + "_" +
                            std::to_string(ranks) + (mode == Mode::Frame ? "f" : "p") + (onRanks ? "" : "0") + ".mp4";
    LoopbackHub hub(ranks);
    std::vector<std::thread> workers;
    for (int r = 1; r < ranks; ++r)
        workers.emplace_back([&, r] {
            LoopbackTransport t(hub, r);
            SharedScene s = shareScene(t, path, nullptr, nullptr);
            EXPECT_EQ(runFarmWorker(t, s, 0.0, 1, 20.0), 0) << "rank " << r;
        });
    LoopbackTransport t(hub, 0);
    RenderJob job;
    SharedScene shared = shareScene(t, path, nullptr, [&](LoadedScene& scene, const FileBundle&) {
        job = jobFor(scene, mode);
        job.output = out;
        job.mp4.chunkFrames = 2;
        job.chunkedFrames = onRanks && chunksOnRenderers(job);
        return encodeWorkerJob(job);
    });
    ChunkedRun run;
    FarmSinks sinks;
    sinks.video = std::make_unique<Mp4Sink>(out, job.settings.width, job.settings.height, job.mp4);
    sinks.frames = std::make_unique<PngCollectingSink>(run.pngs, run.rawFrameWrites);
    FarmOptions opts;
    opts.quiet = true;
    run.outcome = runFarm(t, job, shared, std::move(sinks), opts);
    for (auto& w : workers) w.join();
    std::ifstream f(out, std::ios::binary);
    run.video.assign(std::istreambuf_iterator<char>(f), {});
    return run;
}

}  // namespace

// Issue 32: chunks are encoded on the ranks, never on rank 0. In frame mode each rank renders
// and encodes its chunks (the film's last frames rendered by any rank and sent to the chunk's);
// in pixel mode a rank assembles each chunk from every rank's tiles
// (which go to it, not to rank 0) and encodes it. Either way rank 0 receives PNGs and encoded
// chunks, never pixels, and the file is byte for byte the one rank 0 makes encoding every chunk
// itself from every frame's pixels, at any rank count.
TEST(RunFarm, ChunksEncodedOnTheRanksGiveTheSameFileAtAnyRankCount) {
    const ChunkedRun ref = runChunkedFarm(2, Mode::Pixel, false);
    ASSERT_EQ(ref.outcome.end, FarmEnd::Done) << ref.outcome.error;
    ASSERT_GT(ref.video.size(), 100u);
    EXPECT_EQ(ref.outcome.stats.extraText.at("chunks_encoded_by"), "rank 0");
    EXPECT_EQ(ref.rawFrameWrites, 6);
    const auto frames = rf::testing::referenceFarmFrames();
    for (Mode mode : {Mode::Frame, Mode::Pixel})
    for (int ranks : {1, 2, 3}) {
        SCOPED_TRACE(std::string(mode == Mode::Frame ? "frame" : "pixel") + " mode");
        const ChunkedRun run = runChunkedFarm(ranks, mode);
        ASSERT_EQ(run.outcome.end, FarmEnd::Done) << run.outcome.error;
        EXPECT_TRUE(run.video == ref.video) << ranks << " ranks, chunks on the ranks: another file than rank 0's";
        EXPECT_EQ(run.outcome.stats.extraText.at("chunks_encoded_by"),
                  mode == Mode::Frame ? "the rendering ranks" : "the assembling ranks");
        EXPECT_EQ(run.outcome.stats.extra.at("chunks_from_ranks"), 3.0) << "6 frames in chunks of 2";
        EXPECT_EQ(run.outcome.stats.frames, 6);
        EXPECT_EQ(run.rawFrameWrites, 0) << "pixels reached rank 0's PNG sink";
        ASSERT_EQ(run.pngs.size(), frames.size());
        for (const auto& [f, png] : run.pngs) {
            const std::vector<uint8_t> px = decodePngFrame(png, "frame", 40, 30, 3);
            EXPECT_TRUE(px == frames.at(f)) << ranks << " ranks: PNG of frame " << f << " is not the frame";
        }
        EXPECT_EQ(run.outcome.videoHolds, "the video " + std::string(RAYFARM_TEST_OUT) + "/run_farm/chunked_" +
                                              std::to_string(::getpid()) + "_" + std::to_string(ranks) +
                                              (mode == Mode::Frame ? "f" : "p") + ".mp4 holds frames 0–5 of 0–5");
    }
}
