#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include "anim/frame_ranges.h"

using rf::anim::FrameRange;
using rf::anim::FrameRanges;

TEST(FrameRanges, ABillionFramesAreOneRange) {
    const FrameRanges all = FrameRanges::span(0, 999999999);
    EXPECT_EQ(all.ranges().size(), 1u);
    EXPECT_EQ(all.count(), 1000000000LL);
    EXPECT_TRUE(all.contains(0));
    EXPECT_TRUE(all.contains(999999999));
    EXPECT_FALSE(all.contains(1000000000));
    EXPECT_FALSE(all.contains(-1));
    // Taking a few kept frames out splits the range around them; nothing per frame.
    const FrameRanges rest = all.minus({5, 6, 7, 500000000});
    EXPECT_EQ(rest.ranges(), (std::vector<FrameRange>{{0, 4}, {8, 499999999}, {500000001, 999999999}}));
    EXPECT_EQ(rest.count(), 1000000000LL - 4);
    EXPECT_TRUE(FrameRanges::span(3, 2).empty());
}

TEST(FrameRanges, InsertJoinsNeighboursInAnyOrder) {
    FrameRanges r{9, 3, 5, 4, 3, 7, 8};
    EXPECT_EQ(r.ranges(), (std::vector<FrameRange>{{3, 5}, {7, 9}}));
    r.insert(6);
    EXPECT_EQ(r.ranges(), (std::vector<FrameRange>{{3, 9}}));
    r.insert(1);
    EXPECT_EQ(r.str(), "1, 3–9");
}

TEST(FrameRanges, MatchesASetOnRandomFrames) {
    std::mt19937 rng(7);
    for (int round = 0; round < 50; ++round) {
        std::set<int> a, b;
        FrameRanges ra, rb;
        for (int i = 0; i < 60; ++i) {
            const int f = int(rng() % 100), g = int(rng() % 100);
            a.insert(f);
            ra.insert(f);
            b.insert(g);
            rb.insert(g);
        }
        std::set<int> diff, both;
        for (int f : a) (b.count(f) ? both : diff).insert(f);
        EXPECT_EQ(std::vector<int>(ra.begin(), ra.end()), std::vector<int>(a.begin(), a.end()));
        const FrameRanges d = ra.minus(rb), x = ra.intersect(rb);
        EXPECT_EQ(std::vector<int>(d.begin(), d.end()), std::vector<int>(diff.begin(), diff.end()));
        EXPECT_EQ(std::vector<int>(x.begin(), x.end()), std::vector<int>(both.begin(), both.end()));
        EXPECT_EQ(d.count(), (long long)diff.size());
        for (int f = -1; f <= 100; ++f) EXPECT_EQ(ra.contains(f), a.count(f) == 1) << f;
    }
}

TEST(FrameRanges, CursorWalksEveryFrameOnce) {
    const FrameRanges r{2, 3, 10, 11, 12, 40};
    std::vector<int> seen;
    for (auto c = r.start(); !r.atEnd(c); r.advance(c)) seen.push_back(r.at(c));
    EXPECT_EQ(seen, (std::vector<int>{2, 3, 10, 11, 12, 40}));
    EXPECT_TRUE(FrameRanges{}.atEnd(FrameRanges{}.start()));
}
