#include <gtest/gtest.h>

#include <stdexcept>

#include "farm/cluster/messages.h"

using namespace rf;
using namespace rf::farm;

TEST(Messages, WorkItemAndResultRoundTrip) {
    const WorkItem w{17, {3, 4, 10, 9}};
    const WorkItem w2 = decodeWorkItem(encodeWorkItem(w));
    EXPECT_EQ(w2.frame, 17);
    EXPECT_EQ(w2.rect.x0, 3);
    EXPECT_EQ(w2.rect.y1, 9);

    TileResult r;
    r.item = w;
    r.busySeconds = 0.25;
    r.rays.primary = 35;
    r.rays.shadow = 70;
    r.rays.nonFinite = 2;
    for (int i = 0; i < w.rect.pixels() * 3; ++i) r.rgb.push_back(uint8_t(i * 7));
    const TileResult r2 = decodeTileResult(encodeTileResult(r));
    EXPECT_EQ(r2.item.frame, 17);
    EXPECT_EQ(r2.rgb, r.rgb);
    EXPECT_EQ(r2.rays.shadow, 70u);
    EXPECT_EQ(r2.rays.nonFinite, 2u);
    EXPECT_DOUBLE_EQ(r2.busySeconds, 0.25);

    const Heartbeat h = decodeHeartbeat(encodeHeartbeat({5, 1}));
    EXPECT_EQ(h.currentFrame, 5);
    EXPECT_EQ(h.signalled, 1);
}

TEST(Messages, MalformedPayloadsAreRefused) {
    EXPECT_THROW(decodeWorkItem("abc"), std::runtime_error);
    TileResult r;
    r.item = {0, {0, 0, 2, 2}};
    r.rgb.assign(12, 1);
    std::string bytes = encodeTileResult(r);
    bytes.pop_back();
    EXPECT_THROW(decodeTileResult(bytes), std::runtime_error);
    EXPECT_THROW(decodeHeartbeat(""), std::runtime_error);
}

TEST(Messages, EveryRayCounterTravelsInAResult) {
    // Distinct values in every counter RayStats lists: one the encoding dropped arrives as zero.
    TileResult r;
    r.item = {3, {0, 0, 1, 1}};
    r.rgb.assign(3, 9);
    uint64_t v = 1000;
    for (const RayCounter& c : kRayCounters) r.rays.*c.field = v++;
    const TileResult r2 = decodeTileResult(encodeTileResult(r));
    v = 1000;
    for (const RayCounter& c : kRayCounters) EXPECT_EQ(r2.rays.*c.field, v++) << c.name;
}
