// A rank's ChunkWorkshop with chunked encoding (issue 32): it assembles a chunk's frames from
// tiles that come in any order (some before the chunk's order itself), encodes the chunk
// exactly as from whole frames its own engine rendered (frame mode), refuses a tile that does
// not fit, and routes its own engine's results to the rank that assembles their frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "farm/cluster/chunk_workshop.h"
#include "tests/farm/farm_test_scene.h"
#include "farm/output/png_encoder.h"
#include "farm/output/video_chunk.h"

using namespace rf;
using namespace rf::farm;

namespace {

ChunkVideoSpec testSpec() {
    ChunkVideoSpec spec;
    spec.path = "assembled.mp4";
    spec.width = 40;
    spec.height = 30;
    spec.options.chunkFrames = 2;
    return spec;
}

RenderEngine testEngine() {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    const RenderSettings s = scene.settings;
    return RenderEngine(std::move(scene), std::move(tl), s, 1);
}

/// Chunk c of 2 frames (frames 2c and 2c + 1), PNGs asked for.
ChunkOrder chunkOf2(int c) {
    ChunkOrder o;
    o.item = WorkItem{2 * c, {0, 0, 40, 30}};
    o.item.chunk = c;
    o.item.frames = 2;
    o.sendPngs = 1;
    return o;
}

ChunkOrder chunkZero() { return chunkOf2(0); }

/// frame's tiles of 16x16, rendered alone, for assembling rank `assembler`.
std::vector<TileResult> tilesOf(int frame, int assembler) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    std::vector<TileResult> tiles;
    int applied = -1;
    for (const TileRect& r : makeTiles(40, 30, 16)) {
        WorkItem item{frame, r};
        item.assembler = assembler;
        tiles.push_back(RenderEngine::render(scene, tl, scene.settings, 1, item, applied));
    }
    return tiles;
}

/// The chunk's frames rendered whole by the shop's own engine (frame mode), this rank (1)
/// assembling them: the chunk as it comes back.
std::string renderedWhole(const ChunkOrder& order, std::map<int, std::string>& pngs);

/// Polls until a chunk comes back: its frames' PNGs by frame, and the chunk without its timing
/// (its index in *index when given).
std::string drain(ChunkWorkshop& shop, std::map<int, std::string>& pngs, int* index = nullptr) {
    for (int i = 0; i < 20000; ++i) {
        for (ChunkWorkshop::Outgoing& o : shop.poll(0.001)) {
            EXPECT_EQ(o.dest, 0);
            if (o.tag == kTagChunkFrame) {
                const ChunkFrame f = decodeChunkFrame(o.bytes);
                pngs[f.frame] = f.png;
            } else if (o.tag == kTagChunkDone) {
                std::string bytes;
                decodeChunkDone(o.bytes, bytes);
                EncodedChunk c = parseChunk(bytes);
                c.encodeSeconds = 0.0;
                if (index) *index = c.index;
                return serializeChunk(c);
            }
        }
        EXPECT_EQ(shop.error(), "");
    }
    ADD_FAILURE() << "the chunk never came back";
    return "";
}

std::string renderedWhole(const ChunkOrder& order, std::map<int, std::string>& pngs) {
    RenderEngine engine = testEngine();
    ChunkWorkshop shop(engine, testSpec(), 1);
    shop.submitAssembly(order);
    for (int f = order.item.frame; f < order.item.frame + order.item.frames; ++f) {
        WorkItem item{f, {0, 0, 40, 30}};
        item.assembler = 1;
        engine.submit(item);
    }
    return drain(shop, pngs);
}

}  // namespace

TEST(ChunkWorkshop, AssemblesAChunkFromTilesInAnyOrderAsFromWholeFrames) {
    const auto frames = rf::testing::referenceFarmFrames();
    // Rendered whole on this rank, frame mode's way.
    std::map<int, std::string> wholePngs;
    const std::string expected = renderedWhole(chunkZero(), wholePngs);
    ASSERT_FALSE(expected.empty());
    ASSERT_EQ(wholePngs.size(), 2u);
    for (const auto& [f, png] : wholePngs)
        EXPECT_TRUE(decodePngFrame(png, "frame", 40, 30, 3) == frames.at(f)) << "whole frame " << f << " assembled wrong";

    // The same chunk from 16x16 tiles of frames 0 and 1, shuffled; one arrives before the order.
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    std::vector<TileResult> tiles;
    int applied = -1;
    for (int f : {0, 1})
        for (const TileRect& r : makeTiles(40, 30, 16)) {
            WorkItem item{f, r};
            item.assembler = 1;
            tiles.push_back(RenderEngine::render(scene, tl, scene.settings, 1, item, applied));
        }
    std::shuffle(tiles.begin(), tiles.end(), std::mt19937(7));
    RenderEngine idle = testEngine();
    ChunkWorkshop shop(idle, testSpec(), 1);
    shop.addTile(tiles[0]);
    shop.submitAssembly(chunkZero());
    // Every third tile comes twice (rendered again after its rank was lost, issue 45): the
    // copy changes nothing.
    for (size_t i = 1; i < tiles.size(); ++i) {
        shop.addTile(tiles[i]);
        if (i % 3 == 0) shop.addTile(tiles[i]);
    }
    std::map<int, std::string> pngs;
    EXPECT_TRUE(drain(shop, pngs) == expected) << "the assembled chunk encodes differently";
    ASSERT_EQ(pngs.size(), 2u);
    for (const auto& [f, png] : pngs)
        EXPECT_TRUE(decodePngFrame(png, "frame", 40, 30, 3) == frames.at(f)) << "frame " << f << " assembled wrong";
    EXPECT_EQ(idle.outstanding(), 0) << "an assembled frame was rendered here as well";
}

TEST(ChunkWorkshop, RefusesATileThatDoesNotFitItsFrame) {
    RenderEngine idle = testEngine();
    ChunkWorkshop shop(idle, testSpec(), 1);
    shop.submitAssembly(chunkZero());
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    int applied = -1;
    const TileResult tile = RenderEngine::render(scene, tl, scene.settings, 1, WorkItem{0, {0, 0, 16, 16}}, applied);
    shop.addTile(tile);
    // Issue 45: the same tile again is a copy rendered after its rank was lost, dropped; a tile
    // that covers part of one placed before is an error.
    EXPECT_NO_THROW(shop.addTile(tile)) << "the same tile twice: the copy is dropped";
    TileResult overlapping = RenderEngine::render(scene, tl, scene.settings, 1, WorkItem{0, {8, 0, 24, 16}}, applied);
    EXPECT_THROW(shop.addTile(overlapping), std::runtime_error) << "a tile overlapping one placed before";
    TileResult outside = tile;
    outside.item.rect = {32, 0, 48, 16};  // past the frame's right edge
    EXPECT_THROW(shop.addTile(outside), std::runtime_error);
    TileResult shortTile = tile;
    shortTile.item.rect = {16, 0, 32, 16};
    shortTile.rgb.resize(10);
    EXPECT_THROW(shop.addTile(shortTile), std::runtime_error);
    // Frame mode's whole frame 1, waiting for frame 0 to be complete, comes again: dropped too,
    // as is a tile of it.
    const TileResult whole = RenderEngine::render(scene, tl, scene.settings, 1, WorkItem{1, {0, 0, 40, 30}}, applied);
    shop.addTile(whole);
    EXPECT_NO_THROW(shop.addTile(whole)) << "a whole frame twice";
    TileResult ofWhole = tile;
    ofWhole.item.frame = 1;
    EXPECT_NO_THROW(shop.addTile(ofWhole)) << "a tile of a frame already whole";
}

TEST(ChunkWorkshop, SendsItsEnginesTilesToTheirAssemblerAndTellsRankZero) {
    RenderEngine engine = testEngine();
    ChunkWorkshop shop(engine, testSpec(), 1);
    WorkItem elsewhere{3, {0, 0, 16, 16}};
    elsewhere.assembler = 2;
    engine.submit(elsewhere);
    std::vector<ChunkWorkshop::Outgoing> out;
    for (int i = 0; i < 5000 && out.size() < 2; ++i)
        for (auto& o : shop.poll(0.001)) out.push_back(std::move(o));
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].dest, 0);
    EXPECT_EQ(out[0].tag, kTagTileDone);
    const TileResult note = decodeTileDone(out[0].bytes);
    EXPECT_EQ(note.item.frame, 3);
    EXPECT_EQ(note.item.assembler, 2);
    EXPECT_TRUE(note.rgb.empty()) << "rank 0's note carries no pixels";
    EXPECT_EQ(out[1].dest, 2);
    EXPECT_EQ(out[1].tag, kTagTile);
    EXPECT_EQ(decodeTileResult(out[1].bytes).rgb.size(), 16u * 16u * 3u);

    // A tile this rank assembles stays here: only the note goes out.
    shop.submitAssembly(chunkZero());
    WorkItem here{0, {0, 0, 16, 16}};
    here.assembler = 1;
    engine.submit(here);
    out.clear();
    for (int i = 0; i < 5000 && out.empty(); ++i)
        for (auto& o : shop.poll(0.001)) out.push_back(std::move(o));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].tag, kTagTileDone);
    EXPECT_EQ(out[0].dest, 0);
}

// A rank assembling two chunks whose frames come in turn: the later chunk, complete first, is
// encoded and sent at once (each chunk has its own encoder), not held until the earlier one is.
TEST(ChunkWorkshop, AChunkCompleteFirstIsNotHeldBehindAnEarlierOne) {
    std::map<int, std::string> unused;
    const std::string expected = renderedWhole(chunkOf2(1), unused);

    RenderEngine idle = testEngine();
    ChunkWorkshop shop(idle, testSpec(), 1);
    shop.submitAssembly(chunkOf2(0));
    shop.submitAssembly(chunkOf2(1));
    for (const TileResult& t : tilesOf(0, 1)) shop.addTile(t);  // chunk 0 half done
    for (int f : {2, 3})
        for (const TileResult& t : tilesOf(f, 1)) shop.addTile(t);
    std::map<int, std::string> pngs;
    int index = -1;
    EXPECT_TRUE(drain(shop, pngs, &index) == expected) << "chunk 1 encodes differently beside chunk 0";
    EXPECT_EQ(index, 1);
    EXPECT_EQ(pngs.count(0), 1u);
    EXPECT_EQ(pngs.count(2) + pngs.count(3), 2u);
    EXPECT_EQ(shop.outstanding(), 1) << "chunk 0 still open";
}
