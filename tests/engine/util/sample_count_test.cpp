#include <gtest/gtest.h>

#include "engine/util/sample_count.h"

using namespace rf;

TEST(SampleCount, SquaresAreAccepted) {
    for (int n = 1; n <= 64; ++n) EXPECT_TRUE(isSquareSpp(n * n)) << n * n;
    EXPECT_EQ(sppProblem(16), "");
}

TEST(SampleCount, NonSquaresAndNonPositiveCountsAreRefused) {
    for (int spp : {0, -4, 2, 3, 5, 8, 15, 17, 4095}) EXPECT_FALSE(isSquareSpp(spp)) << spp;
    EXPECT_EQ(sppProblem(5), "expected a square number of samples (1, 4, 9, 16, ...)");
}
