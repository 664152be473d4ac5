#include <gtest/gtest.h>

#include <set>

#include "farm/cluster/chunk_collector.h"
#include "farm/cluster/scheduler.h"

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

// Issue 32: with chunked encoding the chunks are encoded on the ranks, so frame size no longer
// sends auto to pixel mode (rank 0 holds no frames); frame mode shares the film's last frames
// among the ranks, so auto counts frames: frame mode when whole frames handed out in rounds
// keep the ranks busy at least 93% of the time (pixel mode's measured speed against frame
// mode's).
TEST(Scheduler, AutoModeCountsFramesWhenRanksEncodeChunks) {
    std::string why;
    EXPECT_EQ(chooseMode(120, 2, 640, 360, why, 60), Mode::Frame) << "60 rounds, full";
    EXPECT_NE(why.find("120 frame(s) for 2 rendering ranks: whole frames keep the ranks 100% busy"), std::string::npos) << why;
    EXPECT_EQ(chooseMode(120, 2, 640, 360, why, 40), Mode::Frame) << "3 chunks for 2 ranks: their frames are shared";
    EXPECT_EQ(chooseMode(3, 2, 640, 360, why, 2), Mode::Pixel) << "3 frames for 2 ranks: 75% busy";
    EXPECT_NE(why.find("75% busy"), std::string::npos) << why;
    EXPECT_EQ(chooseMode(8, 16, 640, 360, why, 2), Mode::Pixel) << "8 frames for 16 ranks";
    EXPECT_EQ(chooseMode(29, 2, 640, 360, why, 15), Mode::Frame) << "29 frames for 2 ranks: 97% busy";
    EXPECT_EQ(chooseMode(11, 2, 640, 360, why, 15), Mode::Pixel) << "11 frames for 2 ranks: 92% busy";
    EXPECT_EQ(chooseMode(2000000000, 1000, 640, 360, why, 60), Mode::Frame) << "no overflow";
    EXPECT_EQ(chooseMode(480, 2, 3840, 2160, why, 60), Mode::Frame) << "4K in chunks: nothing held on rank 0";
    EXPECT_EQ(chooseMode(480, 2, 3840, 2160, why, 1), Mode::Pixel) << "4K frames to rank 0 (a GIF)";
    EXPECT_EQ(chooseMode(7, 1, 640, 360, why, 60), Mode::Frame) << "one renderer";
}

namespace {

/// An item as text: a chunk's marker "cC>R" (C the chunk, R the rank named to assemble it), a
/// frame "F", or "-" for none.
std::string itemText(const std::optional<WorkItem>& i) {
    if (!i) return "-";
    if (i->chunk >= 0) return "c" + std::to_string(i->chunk) + ">" + std::to_string(i->assembler);
    return std::to_string(i->frame);
}

}  // namespace

// Frame mode with chunked encoding: a rank asking opens a chunk of its own (the marker names it
// to assemble it) and renders that chunk's frames in order; with every chunk open, a rank with
// none of its own left takes the next frames of the chunk with the most left.
TEST(Scheduler, ChunkFrameSchedulerKeepsChunksOnTheirRanksAndSharesTheEnd) {
    const ChunkPlan plan{10, 21, 4};  // chunks 10-13, 14-17, 18-21
    auto s = makeChunkFrameScheduler(plan, {}, 64, 48, 3);
    EXPECT_EQ(s->mode(), Mode::Frame);
    EXPECT_EQ(s->itemsPerFrame(), 1);
    std::vector<std::string> seen;
    auto ask = [&](int rank) {
        const std::optional<WorkItem> i = s->nextFor(rank);
        if (i) {
            EXPECT_EQ(i->chunk < 0 ? i->rect.pixels() : i->frames, i->chunk < 0 ? 64 * 48 : 4) << "a whole frame, or a chunk of 4";
        }
        seen.push_back(itemText(i));
    };
    for (int r : {1, 1, 2, 2, 1, 2, 1, 1, 1, 1}) ask(r);
    EXPECT_EQ(seen, (std::vector<std::string>{"c0>1", "10", "c1>2", "14", "11", "15", "12", "13", "c2>1", "18"}));
    // Every chunk open: rank 1 has 19-21 of its own; rank 2, out of frames, takes chunk 2's next.
    seen.clear();
    for (int r : {2, 2, 2, 1, 2, 2}) ask(r);
    EXPECT_EQ(seen, (std::vector<std::string>{"16", "17", "19", "20", "21", "-"}));
    EXPECT_TRUE(s->exhausted());
}

TEST(Scheduler, ChunkFrameSchedulerHelpsTheChunkWithMostLeftAndSkipsKeptFrames) {
    const ChunkPlan plan{0, 11, 4};  // chunks 0-3, 4-7, 8-11
    anim::FrameRanges kept;
    for (int f : {3, 4, 5, 6, 7, 8}) kept.insert(f);  // chunk 1 kept whole
    auto s = makeChunkFrameScheduler(plan, kept, 8, 8, 2);
    std::vector<std::string> seen;
    auto ask = [&](int rank) { seen.push_back(itemText(s->nextFor(rank))); };
    for (int r : {1, 1, 2, 2}) ask(r);
    // Chunk 1 opens for rank 2 (its assembler encodes the kept frames) but has no frame to hand
    // out; the window of 2 is full, so rank 2 helps chunk 0 (its frame 3 is kept).
    EXPECT_EQ(seen, (std::vector<std::string>{"c0>1", "0", "c1>2", "1"}));
    seen.clear();
    for (int r : {1, 1}) ask(r);
    EXPECT_EQ(seen, (std::vector<std::string>{"2", "-"}));
    EXPECT_FALSE(s->exhausted());
    s->frameReleased();  // chunk 0 passed on
    seen.clear();
    for (int r : {2, 2, 1, 2, 1}) ask(r);
    EXPECT_EQ(seen, (std::vector<std::string>{"c2>2", "9", "10", "11", "-"}));
    EXPECT_TRUE(s->exhausted());
}

TEST(Scheduler, ChunkFrameSchedulerChunksOpenedForNoRankGoToAnyAsker) {
    auto s = makeChunkFrameScheduler(ChunkPlan{0, 3, 2}, {}, 8, 8, 1);
    std::vector<std::string> seen;
    for (auto i = s->next(); i; i = s->next()) seen.push_back(itemText(i));
    EXPECT_EQ(seen, (std::vector<std::string>{"c0>-1", "0", "1"}));
    s->frameReleased();
    seen.clear();
    for (auto i = s->next(); i; i = s->next()) seen.push_back(itemText(i));
    EXPECT_EQ(seen, (std::vector<std::string>{"c1>-1", "2", "3"}));
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

// Issue 45: work taken back from a lost rank goes out before anything new; a chunk whose rank
// was lost opens again (its marker, then every frame of it not kept) without opening a window
// place of its own, and the scheduler is not exhausted until it has.
TEST(Scheduler, RequeuedItemsGoFirstAndALostChunkOpensAgain) {
    auto frames = makeFrameScheduler({0, 1, 2, 3}, 8, 8, 2);
    ASSERT_EQ(frames->take(1)->frame, 0);
    ASSERT_EQ(frames->take(1)->frame, 1);
    EXPECT_FALSE(frames->take(1)) << "the window is full";
    frames->requeue(WorkItem{1, {0, 0, 8, 8}});
    const auto again = frames->take(2);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->frame, 1) << "a requeued item goes out again, window full or not";

    const ChunkPlan plan{0, 11, 4};  // chunks 0-3, 4-7, 8-11
    auto chunked = makeChunkFrameScheduler(plan, {}, 8, 8, 2);
    const auto marker0 = chunked->take(1);
    ASSERT_TRUE(marker0 && marker0->chunk == 0 && marker0->assembler == 1);
    EXPECT_EQ(chunked->take(1)->frame, 0);
    EXPECT_EQ(chunked->take(1)->frame, 1);
    chunked->reopenChunk(0);  // rank 1 lost
    const auto marker0again = chunked->take(2);
    ASSERT_TRUE(marker0again);
    EXPECT_EQ(marker0again->chunk, 0);
    EXPECT_EQ(marker0again->assembler, 2);
    for (int f = 0; f < 4; ++f) EXPECT_EQ(chunked->take(2)->frame, f) << "every frame of the chunk again, in order";
    const auto marker1 = chunked->take(3);
    ASSERT_TRUE(marker1);
    EXPECT_EQ(marker1->chunk, 1) << "the window still had room for one more chunk";

    auto tiles = makeChunkTileScheduler(plan, {}, 8, 8, 4, 1);
    const auto tmarker = tiles->take(1);
    ASSERT_TRUE(tmarker && tmarker->chunk == 0);
    int handed = 0;
    for (; handed < 6; ++handed) ASSERT_TRUE(tiles->take(1));  // frame 0's four tiles, two of frame 1
    tiles->reopenChunk(0);
    const auto tmarker2 = tiles->take(1);
    ASSERT_TRUE(tmarker2);
    EXPECT_EQ(tmarker2->chunk, 0) << "the marker of the chunk opened again";
    std::vector<int> seen;
    while (auto item = tiles->take(1)) {
        if (item->chunk >= 0) break;  // the next chunk, after the window frees
        seen.push_back(item->frame);
    }
    EXPECT_EQ(seen.size(), 16u) << "four frames of four tiles each, from the start";
    EXPECT_EQ(seen.front(), 0);
    EXPECT_FALSE(tiles->exhausted());
}
