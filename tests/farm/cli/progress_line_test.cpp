// Issue 47 #4: the progress line's words, its bar, and the sliding-window rate and ETA, which
// follow frames rendered and so do not jump when a chunk of frames is encoded.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "farm/process/progress.h"

using rf::farm::Progress;
using rf::farm::ProgressCounts;
using rf::farm::RateWindow;

TEST(ProgressLine, SaysRenderedEncodedRateEtaAndWorkers) {
    const ProgressCounts c{45, 30, 3, 2};
    EXPECT_EQ(Progress::text(c, 120, 6.06, 12.4), "45/120 rendered, 30 encoded, 6.1 fps, ETA 0:12, 2/3 workers busy");
    EXPECT_EQ(Progress::text(ProgressCounts{0, 0, 1, 1}, 10, 0.0, -1.0), "0/10 rendered, 0 encoded, 0.0 fps, ETA --, 1/1 workers busy");
    EXPECT_NE(Progress::text(c, 120, 1.0, 3725.0).find(", ETA 1:02:05, "), std::string::npos);
}

TEST(ProgressLine, BarShowsEncodedThenRenderedThenTheRest) {
    EXPECT_EQ(Progress::bar(ProgressCounts{60, 30, 1, 1}, 120, 12), "[###===......]");
    EXPECT_EQ(Progress::bar(ProgressCounts{0, 0, 1, 1}, 120, 4), "[....]");
    EXPECT_EQ(Progress::bar(ProgressCounts{120, 120, 1, 0}, 120, 4), "[####]");
}

TEST(ProgressLine, LiveLineFitsTheTerminal) {
    const ProgressCounts c{45, 30, 3, 2};
    const std::string words = Progress::text(c, 120, 6.1, 12.0);
    const std::string wide = Progress::liveLine("", words, c, 120, 200);
    EXPECT_EQ(wide, Progress::bar(c, 120, Progress::kMaxBar) + " " + words);
    // An 80-column terminal still has a bar, and the whole line fits in 79 columns.
    const std::string eighty = Progress::liveLine("", words, c, 120, 80);
    EXPECT_EQ(eighty.rfind("[", 0), 0u) << eighty;
    EXPECT_LE(eighty.size(), 79u) << eighty;
    EXPECT_NE(eighty.find("] " + words), std::string::npos) << eighty;
    const std::string narrow = Progress::liveLine("", words, c, 120, 50);
    EXPECT_EQ(narrow.size(), 49u) << narrow;  // cut, no bar: a wrapped line would not rewrite in place
    EXPECT_EQ(narrow.find('['), std::string::npos) << narrow;
    EXPECT_EQ(Progress::liveLine("film 2 of 3, B", words, c, 120, 200).rfind("film 2 of 3, B: [", 0), 0u);
}

TEST(RateWindow, RateIsOverTheLastSecondsOnly) {
    RateWindow w(10.0);
    w.add(0.0, 0);
    for (int f = 1; f <= 100; ++f) w.add(f * 0.5, f);  // 2 fps for 50 s
    EXPECT_NEAR(w.rate(), 2.0, 1e-9);
    for (int f = 101; f <= 160; ++f) w.add(50.0 + (f - 100) * 0.2, f);  // then 5 fps for 12 s
    EXPECT_NEAR(w.rate(), 5.0, 0.05) << "the 2 fps of long ago still counts";
    EXPECT_NEAR(w.eta(200), 40 / 5.0, 0.1);
}

TEST(RateWindow, UnknownUntilAFrameIsRendered) {
    RateWindow w;
    w.add(0.0, 0);
    w.add(3.0, 0);
    EXPECT_EQ(w.rate(), 0.0);
    EXPECT_LT(w.eta(10), 0.0);
}

// A film of 120 frames at 5 fps, encoded in chunks of 15: the old line counted frames encoded,
// which stood still for 3 s and then leapt by 15, so its rate and ETA jumped with it. The window
// follows frames rendered, which come one by one: looked at every 0.1 s, the ETA falls by about
// 0.1 s each time, at chunk boundaries as anywhere else. The same window fed the encoded count
// shows the jump the check is there to catch.
namespace {
/// The largest step of the ETA away from falling 0.1 s a tick, after the first 2 s.
double largestEtaStep(bool countEncoded, double* worstError) {
    RateWindow w;
    const int total = 120, chunk = 15;
    double lastEta = -1.0, worst = 0.0;
    *worstError = 0.0;
    for (int tick = 0; tick <= 230; ++tick) {
        const double t = tick * 0.1;
        const int rendered = std::min(total, int(std::floor(t * 5.0 + 1e-9)));
        const int encoded = rendered / chunk * chunk;
        w.add(t, countEncoded ? encoded : rendered);
        const double eta = w.eta(total);
        if (t >= 2.0 && lastEta >= 0.0 && rendered < total) {
            worst = std::max(worst, std::fabs(eta - (lastEta - 0.1)));
            *worstError = std::max(*worstError, std::fabs(eta - (total - rendered) / 5.0));
        }
        lastEta = eta;
    }
    return worst;
}
}  // namespace

TEST(RateWindow, EtaDoesNotJumpAtChunkBoundaries) {
    double error = 0.0;
    const double step = largestEtaStep(false, &error);
    EXPECT_LT(step, 0.6) << "the ETA jumped";
    EXPECT_LT(error, 1.2) << "the ETA is off the true time left";
    double encodedError = 0.0;
    EXPECT_GT(largestEtaStep(true, &encodedError), 2.0) << "the check cannot fail: counting encoded frames should jump";
}

// Eight workers on frames of equal cost (60 s each) finish together: eight frames in a tenth of
// a second, then nothing for a minute. A window of the last 10 s alone keeps only the last two
// frames of a burst, 12 ms apart, and 50 s later shows 0.02 fps where the farm makes 8/60 =
// 0.13. Spanning at least two frames per worker, it stays near the true rate throughout.
TEST(RateWindow, WorkersFinishingTogetherDoNotCollapseTheRate) {
    const double truth = 8.0 / 60.0;
    for (const bool spanFrames : {true, false}) {
        RateWindow w(10.0);
        if (spanFrames) w.setMinFrames(2 * 8);
        w.add(0.0, 0);
        int done = 0;
        double lowest = 1e9, highest = 0.0;
        for (int tick = 1; tick <= 3600; ++tick) {  // 6 minutes, looked at every 0.1 s
            const double t = tick * 0.1;
            if (tick % 600 == 0)
                for (int k = 0; k < 8; ++k) w.add(t + k * 0.0125, ++done);
            else
                w.add(t, done);
            if (t > 130.0) lowest = std::min(lowest, w.rate()), highest = std::max(highest, w.rate());
        }
        if (spanFrames) {
            EXPECT_GT(lowest, 0.5 * truth) << "the rate collapsed between bursts";
            EXPECT_LT(highest, 1.5 * truth) << "the rate leapt at a burst";
        } else {
            EXPECT_LT(lowest, 0.2 * truth) << "the check cannot fail: a 10 s window alone should collapse";
        }
    }
}
