#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include "farm/cluster/frame_assembler.h"
#include "engine/integrators/render.h"

using namespace rf;
using namespace rf::farm;

namespace {

// A tile whose pixels encode (frame, x, y), so misplaced copies show.
TileResult tile(int frame, TileRect r) {
    TileResult t;
    t.item = {frame, r};
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
            t.rgb.push_back(uint8_t(frame));
            t.rgb.push_back(uint8_t(x));
            t.rgb.push_back(uint8_t(y));
        }
    return t;
}

void expectFramePixels(const ReadyFrame& f, int w, int h) {
    ASSERT_EQ(f.rgb.size(), size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const uint8_t* p = f.rgb.data() + 3 * (size_t(y) * w + x);
            ASSERT_EQ(p[0], f.frame);
            ASSERT_EQ(p[1], x);
            ASSERT_EQ(p[2], y);
        }
}

}  // namespace

TEST(FrameAssembler, TilesInAnyOrderLeaveAsWholeFramesInOrder) {
    const int w = 37, h = 21;
    FrameAssembler a(w, h, {0, 1}, {});
    std::vector<TileResult> tiles;
    for (int f : {0, 1})
        for (const TileRect& r : makeTiles(w, h, 8)) tiles.push_back(tile(f, r));
    std::mt19937 rng(7);
    std::shuffle(tiles.begin(), tiles.end(), rng);
    // Deliver all of frame 1 first: nothing may leave before frame 0 is whole.
    std::stable_partition(tiles.begin(), tiles.end(), [](const TileResult& t) { return t.item.frame == 1; });
    ReadyFrame out;
    size_t i = 0;
    for (; tiles[i].item.frame == 1; ++i) {
        a.add(tiles[i]);
        EXPECT_FALSE(a.popReady(out));
    }
    EXPECT_TRUE(a.completed(1) != nullptr);  // frame 1 is whole, though it must wait its turn
    for (; i + 1 < tiles.size(); ++i) EXPECT_FALSE(a.add(tiles[i]));
    EXPECT_FALSE(a.popReady(out));
    EXPECT_TRUE(a.completed(0) == nullptr);
    EXPECT_TRUE(a.add(tiles.back()));
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 0);
    expectFramePixels(out, w, h);
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 1);
    expectFramePixels(out, w, h);
    EXPECT_TRUE(a.finished());
    EXPECT_EQ(a.held(), 0);
}

TEST(FrameAssembler, RefusesOverlapsStrangersAndWrongSizes) {
    FrameAssembler a(16, 16, {4}, {});
    a.add(tile(4, {0, 0, 8, 8}));
    EXPECT_THROW(a.add(tile(4, {4, 4, 12, 12})), std::runtime_error);
    EXPECT_THROW(a.add(tile(5, {0, 0, 8, 8})), std::runtime_error);
    EXPECT_THROW(a.add(tile(4, {8, 8, 17, 16})), std::runtime_error);
    TileResult bad = tile(4, {8, 0, 16, 8});
    bad.rgb.pop_back();
    EXPECT_THROW(a.add(bad), std::runtime_error);
}

TEST(FrameAssembler, KeptFramesTakeTheirTurnInOrder) {
    FrameAssembler a(4, 4, {0, 1, 2}, {1});
    ReadyFrame out;
    EXPECT_FALSE(a.popReady(out));
    a.add(tile(2, {0, 0, 4, 4}));
    EXPECT_FALSE(a.popReady(out));  // frame 0 first
    a.add(tile(0, {0, 0, 4, 4}));
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 0);
    EXPECT_FALSE(out.onDisk);
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 1);
    EXPECT_TRUE(out.onDisk);
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 2);
    EXPECT_TRUE(a.finished());
}

// Issue 30 #2: a film of 10⁹ frames is a range; the assembler holds only the frames in flight.
TEST(FrameAssembler, ABillionFrameFilmHoldsOnlyFramesInFlight) {
    FrameAssembler a(2, 2, anim::FrameRanges::span(0, 999999999), {0, 2});
    ReadyFrame out;
    ASSERT_TRUE(a.popReady(out));
    EXPECT_TRUE(out.onDisk);
    EXPECT_EQ(out.frame, 0);
    EXPECT_THROW(a.add(tile(2, {0, 0, 2, 2})), std::runtime_error);  // kept on disk: not rendered
    EXPECT_TRUE(a.add(tile(1, {0, 0, 2, 2})));
    EXPECT_TRUE(a.add(tile(999999999, {0, 0, 2, 2})));
    EXPECT_EQ(a.held(), 2);
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 1);
    EXPECT_THROW(a.add(tile(1, {0, 0, 2, 2})), std::runtime_error);  // popped already
    ASSERT_TRUE(a.popReady(out));
    EXPECT_EQ(out.frame, 2);
    EXPECT_TRUE(out.onDisk);
    EXPECT_FALSE(a.popReady(out));  // frame 3 next
    EXPECT_EQ(a.popped(), 3);
    EXPECT_FALSE(a.finished());
}
