// RayStats: the counter list is the one place a counter is named (summing, the stats file and
// the farm's messages walk it); stats.h refuses to build if a member is missing from it.
#include <gtest/gtest.h>

#include "engine/util/stats.h"

using namespace rf;

TEST(RayStats, SumAddsEveryListedCounter) {
    RayStats a, b;
    uint64_t v = 1;
    for (const RayCounter& c : kRayCounters) {
        a.*c.field = v;
        b.*c.field = 10 * v++;
    }
    a += b;
    v = 1;
    for (const RayCounter& c : kRayCounters) EXPECT_EQ(a.*c.field, 11 * v++) << c.name;
}
