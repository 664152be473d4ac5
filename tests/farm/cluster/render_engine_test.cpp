// A rank's RenderEngine works on more than one item at a time (issue 32): small tiles of one
// frame queued together are rendered together, their sub-tiles shared among the threads, and
// each comes back as the pixels it has alone.
#include <gtest/gtest.h>

#include <map>

#include "tests/farm/farm_test_scene.h"
#include "farm/cluster/render_engine.h"

using namespace rf;
using namespace rf::farm;

namespace {

std::map<std::pair<int, int>, std::vector<uint8_t>> takeAll(RenderEngine& engine, size_t n) {
    std::map<std::pair<int, int>, std::vector<uint8_t>> out;
    for (int i = 0; i < 10000 && out.size() < n; ++i)
        if (auto r = engine.takeResult(0.01)) out[{r->item.frame, r->item.rect.y0 * 1000 + r->item.rect.x0}] = r->rgb;
    EXPECT_EQ(engine.error(), "");
    return out;
}

}  // namespace

TEST(RenderEngine, RendersSmallTilesOfAFrameTogetherWithTheirOwnPixels) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    const RenderSettings s = scene.settings;
    std::vector<WorkItem> items;
    for (const TileRect& r : makeTiles(s.width, s.height, 8)) items.push_back(WorkItem{2, r});  // 8x8: one sub-tile each
    for (const TileRect& r : makeTiles(s.width, s.height, 16)) items.push_back(WorkItem{4, r});
    ASSERT_EQ(items.size(), 20u + 6u);

    RenderEngine engine(scene, tl, s, 4);
    engine.submitAll(items);
    const auto got = takeAll(engine, items.size());
    ASSERT_EQ(got.size(), items.size());
    // 4 threads, 4 sub-tiles each: the first 16 tiles of frame 2 together; never across frames.
    EXPECT_EQ(engine.largestBatch(), 16);

    int applied = -1;
    LoadedScene aloneLoaded = rf::testing::loadFarmScene();
    Scene& alone = aloneLoaded.scene;
    for (const WorkItem& i : items)
        EXPECT_TRUE(got.at({i.frame, i.rect.y0 * 1000 + i.rect.x0}) == RenderEngine::render(alone, tl, s, 1, i, applied).rgb)
            << "frame " << i.frame << " tile at " << i.rect.x0 << "," << i.rect.y0;
}

TEST(RenderEngine, LargeItemsStillRenderOneByOne) {
    LoadedScene sceneLoaded = rf::testing::loadFarmScene();
    Scene& scene = sceneLoaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(sceneLoaded);
    RenderSettings s = scene.settings;
    s.width = 200;
    s.height = 100;  // each item 200x100, above the small-tile size
    RenderEngine engine(scene, tl, s, 2);
    engine.submitAll(std::vector<WorkItem>{WorkItem{0, {0, 0, 200, 100}}, WorkItem{0, {0, 0, 200, 100}}});
    EXPECT_EQ(takeAll(engine, 1).size(), 1u);
    EXPECT_EQ(engine.largestBatch(), 1);
}
