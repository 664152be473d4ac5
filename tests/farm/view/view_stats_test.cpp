#include "farm/view/view_stats.h"

#include <gtest/gtest.h>

namespace rf::view {
namespace {

TEST(ViewStats, P95IsTheNearestRank) {
    ViewStats s;
    for (int i = 1; i <= 40; ++i) s.frameShown(i * 0.01, true, double(i));  // latencies 1..40 ms
    EXPECT_EQ(s.framesShown(), 40);
    EXPECT_DOUBLE_EQ(s.latencyP95Ms(), 38.0);  // ceil(0.95·40) = 38th of 40
    EXPECT_DOUBLE_EQ(s.latencyMeanMs(), 20.5);
}

TEST(ViewStats, MovingFpsIgnoresRestBetweenMotions) {
    ViewStats s;
    for (int i = 0; i < 11; ++i) s.frameShown(i * 0.05, true, -1.0);        // 10 intervals of 50 ms
    s.frameShown(0.6, false, -1.0);                                          // a refinement at rest
    for (int i = 0; i < 11; ++i) s.frameShown(5.0 + i * 0.05, true, -1.0);  // 4.5 s later: new motion
    EXPECT_EQ(s.movingFrames(), 22);
    EXPECT_NEAR(s.movingFps(), 20.0, 1e-9);  // 20 intervals of 50 ms within motions
    EXPECT_DOUBLE_EQ(s.latencyP95Ms(), 0.0);       // no input-answering frames
}

}  // namespace
}  // namespace rf::view
