#include <gtest/gtest.h>

#include <set>

#include "chunk_collector.h"
#include "scheduler.h"

using namespace rf;
using namespace rf::farm;

namespace {

// Pixel coverage of the items of one frame: each pixel exactly once.
void expectCoversOnce(const std::vector<WorkItem>& items, int frame, int w, int h) {
    std::vector<int> hits(size_t(w) * h, 0);
    for (const WorkItem& i : items) {
        if (i.frame != frame) continue;
        for (int y = i.rect.y0; y < i.rect.y1; ++y)
            for (int x = i.rect.x0; x < i.rect.x1; ++x) ++hits[size_t(y) * w + x];
    }
    for (int v : hits) ASSERT_EQ(v, 1) << "frame " << frame;
}

}  // namespace

TEST(PixelScheduler, HandsOutNextFramesTilesBeforeTheCurrentFrameCompletes) {
    auto s = makePixelScheduler({3, 4, 5}, 50, 30, 16, 2);
    std::vector<WorkItem> got;
    while (auto i = s->next()) got.push_back(*i);
    // Nothing was completed, yet frame 4's tiles went out after frame 3's: no idling at frame ends.
    const int tiles = s->itemsPerFrame();
    EXPECT_EQ(tiles, 4 * 2);  // ceil(50/16) × ceil(30/16)
    ASSERT_EQ(int(got.size()), 2 * tiles);
    EXPECT_EQ(got.front().frame, 3);
    EXPECT_EQ(got.back().frame, 4);
    expectCoversOnce(got, 3, 50, 30);
    expectCoversOnce(got, 4, 50, 30);
    EXPECT_FALSE(s->exhausted());
    EXPECT_EQ(s->openFrames(), 2);
}

TEST(PixelScheduler, WindowBoundsOpenFramesAndReleaseOpensTheNext) {
    auto s = makePixelScheduler({0, 1, 2}, 20, 20, 10, 2);
    std::vector<WorkItem> got;
    while (auto i = s->next()) got.push_back(*i);
    EXPECT_EQ(int(got.size()), 8);
    EXPECT_FALSE(s->next().has_value());
    s->frameReleased();
    std::vector<WorkItem> more;
    while (auto i = s->next()) more.push_back(*i);
    ASSERT_EQ(int(more.size()), 4);
    expectCoversOnce(more, 2, 20, 20);
    EXPECT_TRUE(s->exhausted());
}

TEST(FrameScheduler, HandsOutWholeFramesInOrderWithinTheWindow) {
    auto s = makeFrameScheduler({0, 1, 2, 3, 4, 5, 6}, 64, 48, 3);
    std::vector<int> frames;
    for (int round = 0; round < 10 && !s->exhausted(); ++round) {
        int handed = 0;
        while (auto i = s->next()) {
            EXPECT_EQ(i->rect.x0, 0);
            EXPECT_EQ(i->rect.y0, 0);
            EXPECT_EQ(i->rect.x1, 64);
            EXPECT_EQ(i->rect.y1, 48);
            frames.push_back(i->frame);
            ++handed;
        }
        EXPECT_LE(s->openFrames(), 3);
        s->frameReleased();
    }
    EXPECT_EQ(frames, (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
}

TEST(FrameScheduler, SparseFrameListFromResume) {
    auto s = makeFrameScheduler({2, 7, 9}, 8, 8, 8);
    std::vector<int> frames;
    while (auto i = s->next()) frames.push_back(i->frame);
    EXPECT_EQ(frames, (std::vector<int>{2, 7, 9}));
    EXPECT_TRUE(s->exhausted());
}

TEST(ChooseMode, FewFramesGoPixelManyFramesGoFrame) {
    std::string why;
    EXPECT_EQ(chooseMode(1, 4, 640, 360, why), Mode::Pixel);
    EXPECT_NE(why.find("1 frame"), std::string::npos);
    EXPECT_EQ(chooseMode(120, 2, 640, 360, why), Mode::Frame);
    EXPECT_EQ(chooseMode(120, 1, 640, 360, why), Mode::Frame);
    EXPECT_EQ(chooseMode(120, 2, 7680, 4320, why), Mode::Pixel);
    EXPECT_FALSE(why.empty());
}

// Issue 30 #2: the frames to render of a 10⁹-frame film are ranges, handed out in order.
TEST(FrameScheduler, ABillionFramesStartAtOnce) {
    auto s = makeFrameScheduler(anim::FrameRanges::span(0, 999999999).minus({1, 2}), 8, 8, 3);
    std::vector<int> frames;
    while (auto i = s->next()) frames.push_back(i->frame);
    EXPECT_EQ(frames, (std::vector<int>{0, 3, 4}));
    EXPECT_FALSE(s->exhausted());
    s->frameReleased();
    EXPECT_EQ(s->next()->frame, 5);
}

// Issue 32: with chunked encoding, frame mode's items are chunks, so auto counts chunks; frame
// size no longer sends it to pixel mode (rank 0 holds no frames). Frame mode when whole chunks
// handed out in rounds keep the ranks busy at least 93% of the time (pixel mode's measured speed
// against frame mode's).
TEST(Scheduler, AutoModeCountsChunksWhenRanksEncodeThem) {
    std::string why;
    EXPECT_EQ(chooseMode(120, 2, 640, 360, why, 60), Mode::Frame) << "2 chunks for 2 ranks: one round, full";
    EXPECT_NE(why.find("120 frame(s) in 2 chunk(s) of 60 for 2 rendering ranks: whole chunks keep the ranks 100% busy"),
              std::string::npos) << why;
    EXPECT_EQ(chooseMode(120, 2, 640, 360, why, 40), Mode::Pixel) << "3 chunks for 2 ranks: 75% busy";
    EXPECT_NE(why.find("75% busy"), std::string::npos) << why;
    EXPECT_EQ(chooseMode(120, 16, 640, 360, why, 15), Mode::Pixel) << "8 chunks for 16 ranks";
    EXPECT_EQ(chooseMode(29 * 60, 2, 640, 360, why, 60), Mode::Frame) << "29 chunks for 2 ranks: 97% busy";
    EXPECT_EQ(chooseMode(11 * 60, 2, 640, 360, why, 60), Mode::Pixel) << "11 chunks for 2 ranks: 92% busy";
    EXPECT_EQ(chooseMode(2000000000, 1000, 640, 360, why, 60), Mode::Frame) << "no overflow";
    EXPECT_EQ(chooseMode(480, 2, 640, 360, why, 60), Mode::Frame) << "8 chunks for 2 ranks";
    EXPECT_EQ(chooseMode(480, 2, 3840, 2160, why, 60), Mode::Frame) << "4K in chunks: nothing held on rank 0";
    EXPECT_EQ(chooseMode(480, 2, 3840, 2160, why, 1), Mode::Pixel) << "4K frames to rank 0 (a GIF)";
    EXPECT_EQ(chooseMode(7, 1, 640, 360, why, 60), Mode::Frame) << "one renderer";
}

TEST(Scheduler, ChunkSchedulerHandsOutWholeChunksInOrderWithinItsWindow) {
    const ChunkPlan plan{10, 20, 4};  // chunks 10-13, 14-17, 18-20
    auto s = makeChunkScheduler(plan, 64, 48, 2);
    auto a = s->next(), b = s->next();
    ASSERT_TRUE(a && b);
    EXPECT_FALSE(s->next()) << "window of 2 chunks";
    EXPECT_EQ(a->chunk, 0);
    EXPECT_EQ(a->frame, 10);
    EXPECT_EQ(a->frames, 4);
    EXPECT_EQ(a->rect.pixels(), 64 * 48);
    EXPECT_EQ(b->chunk, 1);
    s->frameReleased();
    auto c = s->next();
    ASSERT_TRUE(c);
    EXPECT_EQ(c->chunk, 2);
    EXPECT_EQ(c->frame, 18);
    EXPECT_EQ(c->frames, 3);
    EXPECT_TRUE(s->exhausted());
}

// Pixel mode with chunked encoding: a marker per chunk as it opens (the master picks its
// assembler there), then whole frames' tiles, the open chunks taking turns frame by frame, kept
// frames skipped; the window counts chunks.
TEST(Scheduler, ChunkTileSchedulerOpensChunksThenTakesTheirFramesInTurn) {
    const ChunkPlan plan{10, 20, 4};  // chunks 10-13, 14-17, 18-20
    anim::FrameRanges kept;
    for (int f : {11, 14, 15, 16, 17}) kept.insert(f);
    auto s = makeChunkTileScheduler(plan, kept, 64, 32, 32, 2);  // 2 tiles a frame
    std::vector<std::string> seen;
    auto take = [&] {
        std::optional<WorkItem> i = s->next();
        if (!i) return false;
        seen.push_back(i->rect.pixels() == 0 ? "c" + std::to_string(i->chunk) + ":" + std::to_string(i->frame) + "+" +
                                                   std::to_string(i->frames)
                                             : std::to_string(i->frame) + "@" + std::to_string(i->rect.x0));
        return true;
    };
    while (take()) {}
    // Chunk 1 is kept whole: it opens (its assembler encodes the kept frames) but hands out no tile.
    EXPECT_EQ(seen, (std::vector<std::string>{"c0:10+4", "c1:14+4", "10@0", "10@32", "12@0", "12@32", "13@0", "13@32"}));
    EXPECT_FALSE(s->exhausted());
    EXPECT_EQ(s->itemsPerFrame(), 2);
    EXPECT_EQ(s->mode(), Mode::Pixel);
    s->frameReleased();
    seen.clear();
    while (take()) {}
    EXPECT_EQ(seen, (std::vector<std::string>{"c2:18+3", "18@0", "18@32", "19@0", "19@32", "20@0", "20@32"}));
    EXPECT_TRUE(s->exhausted());
}

TEST(Scheduler, ChunkTileSchedulerAlternatesBetweenOpenChunks) {
    auto s = makeChunkTileScheduler(ChunkPlan{0, 5, 3}, {}, 16, 16, 16, 2);  // 1 tile a frame
    std::vector<int> frames;
    for (auto i = s->next(); i; i = s->next())
        if (i->rect.pixels() > 0) frames.push_back(i->frame);
    EXPECT_EQ(frames, (std::vector<int>{0, 3, 1, 4, 2, 5}));
    EXPECT_TRUE(s->exhausted());
}

TEST(Scheduler, ChunkCollectorPassesChunksOnInFilmOrder) {
    ChunkCollector c(ChunkPlan{0, 9, 4});  // 3 chunks
    int index = -1;
    std::string bytes;
    c.add(2, "two");
    c.holdPixels(9, {9});
    c.holdPixels(1, {1});
    EXPECT_FALSE(c.popReady(index, bytes));
    c.add(0, "zero");
    ASSERT_TRUE(c.popReady(index, bytes));
    EXPECT_EQ(index, 0);
    EXPECT_EQ(bytes, "zero");
    EXPECT_EQ(c.takePixels(0).size(), 1u);
    EXPECT_FALSE(c.popReady(index, bytes));
    EXPECT_THROW(c.add(0, "again"), std::runtime_error) << "a chunk already passed on";
    EXPECT_THROW(c.add(2, "twice"), std::runtime_error);
    EXPECT_THROW(c.add(3, "beyond"), std::runtime_error);
    c.add(1, "one");
    ASSERT_TRUE(c.popReady(index, bytes));
    ASSERT_TRUE(c.popReady(index, bytes));
    EXPECT_EQ(index, 2);
    const auto px = c.takePixels(2);
    ASSERT_EQ(px.size(), 1u);
    EXPECT_EQ(px[0].first, 9);
    EXPECT_TRUE(c.finished());
    EXPECT_EQ(c.framesPopped(), 10);
}
