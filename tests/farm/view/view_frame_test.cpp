#include "farm/view/view_frame.h"

#include <gtest/gtest.h>

namespace rf::view {
namespace {

TEST(ViewFrame, RefinementPassesEndAtTheTarget) {
    EXPECT_EQ(refinementSpp(1), (std::vector<int>{1}));
    EXPECT_EQ(refinementSpp(9), (std::vector<int>{1, 4, 9}));
    EXPECT_EQ(refinementSpp(16), (std::vector<int>{1, 4, 16}));
    EXPECT_EQ(refinementSpp(64), (std::vector<int>{1, 4, 16, 64}));
}

TEST(ViewFrame, MovingResolutionHoldsTheFrameTime) {
    // Over the budget: half the resolution (down to a quarter); far under it: back up.
    EXPECT_EQ(nextMovingScale(1, kMovingFrameMs + 5.0), 2);
    EXPECT_EQ(nextMovingScale(2, kMovingFrameMs + 5.0), 4);
    EXPECT_EQ(nextMovingScale(4, 10.0 * kMovingFrameMs), 4);
    EXPECT_EQ(nextMovingScale(4, 0.1 * kMovingFrameMs), 2);
    // In between (4x the pixels would overrun): stay.
    EXPECT_EQ(nextMovingScale(2, 0.5 * kMovingFrameMs), 2);
    EXPECT_EQ(nextMovingScale(1, 0.1 * kMovingFrameMs), 1);
}

TEST(ViewFrame, MovingScaleStepsDownAtOnceAndUpAfterARun) {
    MovingScale m;
    EXPECT_EQ(m.next(kMovingFrameMs + 5.0), 2);  // one slow frame halves the resolution
    EXPECT_EQ(m.next(kMovingFrameMs + 5.0), 4);
    for (int i = 1; i < MovingScale::kFirstRun; ++i) EXPECT_EQ(m.next(0.1 * kMovingFrameMs), 4) << i;
    EXPECT_EQ(m.next(0.1 * kMovingFrameMs), 2);  // the run is complete
    // A frame in between breaks a run: it starts again.
    for (int i = 1; i < MovingScale::kFirstRun; ++i) m.next(0.1 * kMovingFrameMs);
    EXPECT_EQ(m.next(0.5 * kMovingFrameMs), 2);
    for (int i = 1; i < MovingScale::kFirstRun; ++i) EXPECT_EQ(m.next(0.1 * kMovingFrameMs), 2) << i;
    EXPECT_EQ(m.next(0.1 * kMovingFrameMs), 1);
}

TEST(ViewFrame, AStepUpTheNextFrameUndoesDoublesTheRun) {
    MovingScale m;
    m.next(kMovingFrameMs + 5.0);  // scale 2
    for (int i = 0; i < MovingScale::kFirstRun; ++i) m.next(0.1 * kMovingFrameMs);
    ASSERT_EQ(m.scale(), 1);
    EXPECT_EQ(m.next(kMovingFrameMs + 5.0), 2);  // the full size was too slow after all
    for (int i = 1; i < 2 * MovingScale::kFirstRun; ++i) EXPECT_EQ(m.next(0.1 * kMovingFrameMs), 2) << i;
    EXPECT_EQ(m.next(0.1 * kMovingFrameMs), 1);
}

}  // namespace
}  // namespace rf::view
