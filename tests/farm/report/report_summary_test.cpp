// summary.md: the cheapest setting within the target, and the ray kinds a scene left out.
#include <gtest/gtest.h>

#include "farm/report/report_summary.h"
#include "tests/farm/report/report_test_scene.h"

namespace rf::report {
namespace {

SweepRow row(double s, double psnr, QualitySetting q = {}) {
    SweepRow r;
    r.q = q;
    r.seconds = s;
    r.error.psnr = psnr;
    r.error.rmse = std::pow(10.0, -psnr / 20.0);
    return r;
}

TEST(ReportSummary, CheapestWithinPicksTheFastestRowMeetingTheTarget) {
    const std::vector<SweepRow> rows = {row(0.5, 25), row(2.0, 35), row(1.0, 31), row(4.0, 40)};
    ASSERT_NE(cheapestWithin(rows, 30.0), nullptr);
    EXPECT_EQ(cheapestWithin(rows, 30.0)->seconds, 1.0);
    EXPECT_EQ(cheapestWithin(rows, 35.0)->seconds, 2.0);  // exactly on the target counts
    EXPECT_EQ(cheapestWithin(rows, 41.0), nullptr);
}

TEST(ReportSummary, SceneWithoutGlassNamesTheMissingRefractionRays) {
    const Scene sc = testing::edgeScene(false);
    RayStats rays;
    rays.primary = 10;
    rays.shadow = 5;
    rays.reflection = 3;
    const auto notes = missingRayKinds(rays, sc);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("no glass"), std::string::npos) << notes[0];
}

TEST(ReportSummary, SceneWithoutLightsNamesTheMissingShadowRays) {
    const Scene sc = testing::edgeScene(true, false);
    RayStats rays;
    rays.primary = 10;
    rays.reflection = 3;
    rays.refraction = 2;
    const auto notes = missingRayKinds(rays, sc);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("no lights"), std::string::npos) << notes[0];
}

TEST(ReportSummary, GlassOutOfViewIsToldApartFromNoGlass) {
    const Scene sc = testing::edgeScene(true);
    RayStats rays;
    rays.primary = 10;
    rays.shadow = 1;
    rays.reflection = 1;
    const auto notes = missingRayKinds(rays, sc);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("out of view"), std::string::npos) << notes[0];
}

TEST(ReportSummary, EveryKindPresentGivesNoNotes) {
    RayStats rays;
    rays.primary = rays.shadow = rays.reflection = rays.refraction = 1;
    EXPECT_TRUE(missingRayKinds(rays, testing::edgeScene(true)).empty());
}

TEST(ReportSummary, MarkdownNamesTheAnswerOrSaysNoneReachesTheTarget) {
    std::vector<SweepRow> rows = {row(0.5, 25, {1, 5, 1e-3f}), row(1.0, 31, {4, 5, 1e-3f})};
    rows[0].isDefault = true;
    SummaryInfo info;
    info.sceneName = "x.json";
    info.targetPsnr = 30;
    const std::string md = summaryMarkdown(info, rows);
    EXPECT_NE(md.find("**spp 4, depth 5, min weight 0.001, indirect 0, bounce 3**"), std::string::npos) << md;
    EXPECT_NE(md.find("## The default setting"), std::string::npos);
    info.targetPsnr = 50;
    const std::string none = summaryMarkdown(info, rows);
    EXPECT_NE(none.find("No setting of the sweep reaches 50 dB"), std::string::npos) << none;
    EXPECT_NE(none.find("The closest is spp 4"), std::string::npos) << none;
}

}  // namespace
}  // namespace rf::report
