// The quality sweep: which settings, Pareto marking, and error against a real reference render.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/util/image.h"
#include "farm/report/report_sweep.h"
#include "tests/farm/report/report_test_scene.h"

namespace rf::report {
namespace {

TEST(ReportSweep, OneFactorAtATimeHasEachValueOnceAroundTheBase) {
    SweepSpec spec;  // spp 1,4,16,64; depth 1..8; min weight 0,1e-3,1e-2,0.1
    spec.base = {1, 5, 1e-3f};
    const auto pts = makeSweep(spec);
    // The base lies on four lines, so it is shared: 4 + 8 + 4 + 4 − 3; its bounce (3 thousand
    // points) is not on that line's list (0, 1, 4, 16): four more.
    EXPECT_EQ(pts.size(), 17u + 4u);
    EXPECT_EQ(pts[0].q, spec.base);
    for (size_t i = 0; i < pts.size(); ++i)
        for (size_t j = i + 1; j < pts.size(); ++j) EXPECT_FALSE(pts[i].q == pts[j].q) << i << " " << j;
    // Every non-base point differs from the base in exactly one knob.
    for (const SweepPoint& p : pts) {
        const int diff = (p.q.value("spp") != 1) + (p.q.value("depth") != 5) + (p.q.value("min_weight") != 1e-3f) +
                         (p.q.value("indirect") != 0) + (p.q.value("bounce") != kDefaultBounce);
        EXPECT_LE(diff, 1) << describe(p.q);
    }
}

TEST(ReportSweep, BaseOutsideTheListsIsAddedOnce) {
    SweepSpec spec;
    spec.base = {9, 12, 0.5f};
    // Its indirect samples (0, the default) are on that list: that point is the base itself; its
    // bounce (3, the default) is not on that one.
    EXPECT_EQ(makeSweep(spec).size(), 1u + 4 + 8 + 4 + 3 + 4);
}

TEST(ReportSweep, FullGridHasEveryCombination) {
    SweepSpec spec;
    spec.kind = SweepKind::FullGrid;
    spec.base = {1, 5, 1e-3f, 0, 4};  // on every list
    EXPECT_EQ(makeSweep(spec).size(), 4u * 8 * 4 * 4 * 4);
}

SweepRow row(double s, double rmse) {
    SweepRow r;
    r.seconds = s;
    r.error.rmse = rmse;
    return r;
}

TEST(ReportSweep, ParetoFrontKeepsOnlyUndominatedRows) {
    std::vector<SweepRow> rows = {row(1, 0.1), row(2, 0.05), row(2, 0.2), row(3, 0.05), row(4, 0.01), row(0.5, 0.3)};
    markPareto(rows);
    const bool expect[] = {true, true, false, false, true, true};
    for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i].pareto, expect[i]) << i;
}

TEST(ReportSweep, EqualRowsAreBothOnTheFront) {
    std::vector<SweepRow> rows = {row(1, 0.1), row(1, 0.1)};
    markPareto(rows);
    EXPECT_TRUE(rows[0].pareto && rows[1].pareto);
}

TEST(ReportSweep, ErrorShrinksAsSamplesGrowOnASceneWithEdges) {
    const Scene sc = testing::edgeScene(false);
    RenderSettings s = sc.settings;
    const TimedRender ref = renderTimed(sc, withQuality(s, {256, 8, 0.f}), 0, 2, 0.0, 1);
    const auto ref8 = toRgb8(ref.image, s.toneMap);
    SweepSpec spec;
    spec.list("spp") = {1, 4, 16, 64};
    spec.list("depth") = {8};
    spec.list("min_weight") = {0.f};
    spec.list("indirect") = {0};
    spec.list("bounce") = {kDefaultBounce};  // bounce light lights no material of these scenes
    spec.base = {1, 8, 0.f};
    const auto rows = runSweep(sc, s, spec, ref8, 0, 2);
    ASSERT_EQ(rows.size(), 4u);
    for (size_t i = 0; i + 1 < rows.size(); ++i) {
        EXPECT_LT(rows[i + 1].error.rmse, rows[i].error.rmse) << describe(rows[i + 1].q);
        EXPECT_GT(rows[i + 1].error.ssim, rows[i].error.ssim) << describe(rows[i + 1].q);
        EXPECT_EQ(rows[i + 1].rays.primary, 4 * rows[i].rays.primary);
    }
    EXPECT_GT(rows[0].error.rmse, 0.0);  // edges exist: one sample per pixel is not the reference
}

TEST(ReportSweep, TheReferenceSettingScoresInfinitePsnrAgainstTheReference) {
    const Scene sc = testing::edgeScene(true);
    RenderSettings s = sc.settings;
    const QualitySetting refQ{16, 8, 0.f};
    const TimedRender ref = renderTimed(sc, withQuality(s, refQ), 0, 2, 0.0, 1);
    SweepSpec spec;
    spec.list("spp") = {16};
    spec.list("depth") = {8};
    spec.list("min_weight") = {0.f};
    spec.list("indirect") = {0};
    spec.list("bounce") = {kDefaultBounce};  // bounce light lights no material of these scenes
    spec.base = refQ;
    const auto rows = runSweep(sc, s, spec, toRgb8(ref.image, s.toneMap), 0, 2);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].error.rmse, 0.0);
    EXPECT_TRUE(std::isinf(rows[0].error.psnr));
    EXPECT_DOUBLE_EQ(rows[0].error.ssim, 1.0);
}

TEST(ReportSweep, RepeatsStopAtTheTimingBudgetOrTheRepeatLimit) {
    const Scene sc = testing::edgeScene(false);
    SweepSpec spec;
    spec.list("spp") = {1};
    spec.list("depth") = {2};
    spec.list("min_weight") = {0.f};
    spec.list("indirect") = {0};
    spec.list("bounce") = {kDefaultBounce};  // bounce light lights no material of these scenes
    spec.base = {1, 2, 0.f};
    spec.maxRepeats = 4;
    spec.minTimingSeconds = 1e9;  // never reached: the limit decides
    const auto ref8 = toRgb8(renderTimed(sc, sc.settings, 0, 1, 0.0, 1).image, sc.settings.toneMap);
    EXPECT_EQ(runSweep(sc, sc.settings, spec, ref8, 0, 1)[0].repeats, 4);
    spec.minTimingSeconds = 0.0;  // reached after the first render
    EXPECT_EQ(runSweep(sc, sc.settings, spec, ref8, 0, 1)[0].repeats, 1);
}

TEST(ReportSweep, DepthOneTracesNoSecondaryRays) {
    const Scene sc = testing::edgeScene(true);
    const TimedRender r = renderTimed(sc, withQuality(sc.settings, {1, 1, 0.f}), 0, 1, 0.0, 1);
    EXPECT_EQ(r.rays.primary, 48u * 32u);
    EXPECT_EQ(r.rays.reflection, 0u);
    EXPECT_EQ(r.rays.refraction, 0u);
    EXPECT_EQ(r.repeats, 1);
}

}  // namespace
}  // namespace rf::report
