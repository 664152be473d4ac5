// The whole quality report on a tiny scene: every file written, every row in the CSV, a plot
// that decodes, a summary that names what the scene left out; and the CLI's refusals.
#include "farm/report/report_run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "farm/cli/cli.h"
#include "farm/report/cmd_report.h"
#include "engine/util/errors.h"
#include "engine/util/image.h"
#include "farm/report/report_csv.h"
#include "tests/farm/report/report_test_scene.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::report {
namespace {

std::vector<std::vector<std::string>> readCsv(const std::string& path) {
    std::ifstream f(path);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(f, line)) {
        std::vector<std::string> cells;
        std::istringstream in(line);
        std::string c;
        while (std::getline(in, c, ',')) cells.push_back(c);
        rows.push_back(cells);
    }
    return rows;
}

/// The cell of row in the column named name (looked up in the header row).
const std::string& cell(const std::vector<std::vector<std::string>>& csv, size_t row, const std::string& name) {
    const auto& head = csv.at(0);
    const auto it = std::find(head.begin(), head.end(), name);
    if (it == head.end()) throw std::out_of_range("no CSV column " + name);
    return csv.at(row).at(size_t(it - head.begin()));
}

std::string readText(const std::string& path) {
    std::ifstream f(path);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

QualityReportOptions tinyOptions(const std::string& dir) {
    QualityReportOptions o;
    o.outDir = dir;
    o.sceneName = "tiny";
    o.threads = 2;
    o.progress = false;
    o.sweep.list("spp") = {1, 4, 16};
    o.sweep.list("depth") = {1, 2, 5};
    o.sweep.list("min_weight") = {0.f, 0.1f};
    o.sweep.list("indirect") = {0};
    o.sweep.list("bounce") = {kDefaultBounce};  // bounce light lights no material of this scene
    o.sweep.base = {1, 5, 1e-3f};
    o.reference = {64, 8, 0.f};
    o.targetPsnr = 20.0;
    return o;
}

TEST(ReportRun, WritesEveryRowAPlotThatDecodesAndASummary) {
    const Scene sc = testing::edgeScene(false);
    const QualityReportOptions o = tinyOptions(testing::freshDir("report_run_tiny"));
    const QualityReport rep = runQualityReport(sc, sc.settings, o);

    const size_t expectRows = makeSweep(o.sweep).size();
    EXPECT_EQ(expectRows, 1u + 2 + 2 + 2);  // the base, then each list less the base's own value
    const auto csv = readCsv(rep.csvPath);
    ASSERT_EQ(csv.size(), 1 + 1 + expectRows);  // header, reference, sweep
    const std::string header = csvHeader();
    const size_t columns = std::count(header.begin(), header.end(), ',') + 1;
    for (const auto& r : csv) EXPECT_EQ(r.size(), columns);
    EXPECT_EQ(csv[1][0], "reference");
    EXPECT_EQ(cell(csv, 1, "psnr_db"), "inf");  // the reference against itself
    EXPECT_EQ(cell(csv, 1, "rmse"), "0");
    int defaults = 0;
    for (size_t i = 2; i < csv.size(); ++i) {
        defaults += cell(csv, i, "is_default") == "1";
        EXPECT_TRUE(std::isfinite(std::stod(cell(csv, i, "psnr_db")))) << i;  // nothing else matches exactly
        EXPECT_GT(std::stod(cell(csv, i, "seconds")), 0.0);
    }
    EXPECT_EQ(defaults, 1);

    int w = 0, h = 0;
    const auto plot = readImageRgb8(rep.plotPath, w, h);
    EXPECT_EQ(w, 960);
    EXPECT_EQ(h, 640);
    EXPECT_EQ(plot.size(), size_t(w) * h * 3);
    const auto err = readImageRgb8(rep.errorImagePath, w, h);
    EXPECT_EQ(w, 48);
    EXPECT_EQ(h, 32);

    const std::string md = readText(rep.summaryPath);
    EXPECT_NE(md.find("No refraction rays: no material transmits light (no glass)."), std::string::npos) << md;
    EXPECT_EQ(md.find("No shadow rays"), std::string::npos) << md;
    EXPECT_NE(md.find("## Cheapest setting within 20 dB PSNR"), std::string::npos) << md;
    EXPECT_EQ(rep.reference.rays.refraction, 0u);
}

TEST(ReportRun, SceneWithGlassAndLightsUsesEveryRayKind) {
    const Scene sc = testing::edgeScene(true);
    QualityReportOptions o = tinyOptions(testing::freshDir("report_run_glass"));
    o.plot = false;
    o.sweep.list("spp") = {1};
    o.sweep.list("depth") = {5};
    o.sweep.list("min_weight") = {1e-3f};
    o.sweep.list("indirect") = {0};
    o.sweep.list("bounce") = {kDefaultBounce};  // bounce light lights no material of this scene
    const QualityReport rep = runQualityReport(sc, sc.settings, o);
    EXPECT_TRUE(rep.rayNotes.empty());
    EXPECT_GT(rep.reference.rays.refraction, 0u);
    EXPECT_NE(readText(rep.summaryPath).find("The scene uses every ray kind."), std::string::npos);
}

/// A picture of sc at q written as a PNG: an "external" reference that equals one render.
std::string writeRender(const Scene& sc, const QualitySetting& q, const std::string& path) {
    const RenderSettings s = withQuality(sc.settings, q);
    writePng(path, s.width, s.height, toRgb8(renderTimed(sc, s, 0, 2, 0.0, 1).image, s));
    return path;
}

TEST(ReportRun, AnExternalReferenceEqualToOneRenderScoresThatSettingExactly) {
    const Scene sc = testing::edgeScene(true);
    const std::string dir = testing::freshDir("report_run_external");
    std::filesystem::create_directories(dir + "/out");
    QualityReportOptions o = tinyOptions(dir + "/out");
    o.sweep.list("spp") = {1, 4, 16};
    o.sweep.list("depth") = {5};
    o.sweep.list("min_weight") = {1e-3f};
    o.sweep.list("indirect") = {0};
    o.sweep.list("bounce") = {kDefaultBounce};  // bounce light lights no material of this scene
    const QualitySetting match{4, 5, 1e-3f};
    o.external = readExternalReference(writeRender(sc, match, dir + "/external.png"));
    const QualityReport rep = runQualityReport(sc, sc.settings, o);

    ASSERT_EQ(rep.rows.size(), 3u);
    for (const SweepRow& r : rep.rows) {
        if (r.q == normalized(match)) {
            EXPECT_EQ(r.error.rmse, 0.0);
            EXPECT_TRUE(std::isinf(r.error.psnr));
            EXPECT_DOUBLE_EQ(r.error.ssim, 1.0);
        } else {  // another picture of the same scene: close, not equal
            EXPECT_GT(r.error.rmse, 0.0) << describe(r.q);
            EXPECT_TRUE(std::isfinite(r.error.psnr)) << describe(r.q);
            EXPECT_LT(r.error.ssim, 1.0) << describe(r.q);
            EXPECT_GT(r.error.ssim, 0.5) << describe(r.q);
        }
    }
    EXPECT_TRUE(rep.reference.external);
    EXPECT_EQ(rep.referencePath, dir + "/external.png");
    EXPECT_FALSE(std::filesystem::exists(dir + "/out/reference.png"));  // nothing rendered as the reference
    const auto csv = readCsv(rep.csvPath);
    ASSERT_EQ(csv.size(), 1u + 1 + 3);
    EXPECT_EQ(cell(csv, 1, "factor"), "reference");
    EXPECT_EQ(cell(csv, 1, "psnr_db"), "inf");
    EXPECT_EQ(cell(csv, 1, "spp"), "");      // no setting
    EXPECT_EQ(cell(csv, 1, "seconds"), "");  // and no time
    const std::string md = readText(rep.summaryPath);
    EXPECT_NE(md.find("Reference: `" + dir + "/external.png`, an image made elsewhere"), std::string::npos) << md;
    EXPECT_EQ(md.find("faster than the reference"), std::string::npos) << md;
    EXPECT_NE(md.find("Most rays of each kind"), std::string::npos) << md;
}

TEST(ReportRun, AnExternalReferenceOfAnotherSizeIsRefused) {
    const Scene sc = testing::edgeScene(false);
    const std::string dir = testing::freshDir("report_run_external_size");
    Scene small = sc;
    small.settings.width = 24;
    small.settings.height = 16;
    QualityReportOptions o = tinyOptions(dir);
    o.external = readExternalReference(writeRender(small, {1, 5, 1e-3f}, dir + "/small.png"));
    EXPECT_THROW(runQualityReport(sc, sc.settings, o), InputError);
    EXPECT_FALSE(std::filesystem::exists(dir + "/report.csv"));
}

std::string writeScene(const std::string& dir) {
    const std::string path = dir + "/tiny.json";
    std::ofstream(path) << R"({"camera": {"eye": [0, 2, -5], "target": [0, 0.5, 0]},
      "render": {"width": 24, "height": 16},
      "materials": {"m": {"color": [0.8, 0.3, 0.2]}},
      "objects": [{"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "m"}]})";
    return path;
}

TEST(ReportCli, RefusesBadOptionsBeforeRendering) {
    const std::string dir = testing::freshDir("report_cli");
    const std::string scene = writeScene(dir);
    using rf::UsageError;
    EXPECT_THROW(cli::runReport({scene}), UsageError);  // no --out
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--sweep-spp", "1,3"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--sweep-depth", "0"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--sweep-min-weight", "x"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--sweep-indirect", "1.5"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--sweep-indirect", "-1"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--grid", "half"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--ref-spp", "10"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--frame", "1"}), UsageError);  // one frame only
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--target-psnr", "nan"}), UsageError);
    EXPECT_THROW(cli::runReport({"--stability", scene, "--out", dir}), UsageError);
    EXPECT_FALSE(std::filesystem::exists(dir + "/report.csv"));
}

TEST(ReportCli, RunsEndToEndOnASceneFile) {
    const std::string dir = testing::freshDir("report_cli_run");
    const std::string scene = writeScene(dir);
    const std::string out = dir + "/out";
    EXPECT_EQ(cli::runReport({scene, "--out", out, "--sweep-spp", "1,4", "--sweep-depth", "1,2", "--sweep-min-weight",
                              "0", "--sweep-indirect", "0", "--ref-spp", "16", "--threads", "1", "--video-crf", "18,40",
                              "--video-preset", "ultrafast"}),
              0);
    const auto csv = readCsv(out + "/report.csv");
    // Base (scene default 1 spp, depth 5, 1e-3) + 2 + 2 + 1 − 1 (base on the spp line).
    EXPECT_EQ(csv.size(), 2u + 5u);
    const std::string md = readText(out + "/summary.md");
    EXPECT_NE(md.find("No shadow rays: the scene has no lights"), std::string::npos) << md;
    EXPECT_NE(md.find("No reflection rays: no material reflects"), std::string::npos) << md;
    // The video part: the lossless decode check and one row per CRF, all in one frame (a still scene).
    const auto video = readCsv(out + "/video.csv");
    ASSERT_EQ(video.size(), 1u + 1u + 2u);
    EXPECT_EQ(video[1][2], "1");     // lossless
    EXPECT_EQ(video[1][8], "inf");   // decodes bit for bit
    EXPECT_EQ(video[2][3], "1");     // frames
    EXPECT_GT(std::stod(video[2][8]), std::stod(video[3][8]));  // CRF 18 beats CRF 40
    EXPECT_NE(md.find("Decode check: the lossless encode"), std::string::npos) << md;
    int w = 0, h = 0;
    readImageRgb8(out + "/video_psnr_vs_fps.png", w, h);
    EXPECT_EQ(w, 960);
}

TEST(ReportCli, FramePosesTheSceneByItsTimeline) {
    const std::string dir = testing::freshDir("report_cli_frame");
    const std::string scene = dir + "/orbit.json";
    std::ofstream(scene) << R"({"camera": {"eye": [0, 2, -5], "target": [0, 0.5, 0]},
      "render": {"width": 24, "height": 16},
      "materials": {"m": {"color": [0.8, 0.3, 0.2]}, "f": {"color": [0.9, 0.9, 0.9]}},
      "lights": [{"type": "point", "position": [3, 5, -3]}],
      "objects": [{"type": "sphere", "center": [0.8, 0.5, 0], "radius": 0.5, "material": "m"},
                  {"type": "plane", "normal": [0, 1, 0], "point": [0, 0, 0], "material": "f"}],
      "timeline": {"fps": 10, "duration": 1,
                   "camera": {"orbit": {"center": [0, 0, 0], "radius": 5, "height": 2, "period": 1}}}})";
    auto run = [&](const std::string& frame) {
        const std::string out = dir + "/f" + frame;
        EXPECT_EQ(
            cli::runReport({scene, "--out", out, "--frame", frame, "--no-video", "--sweep-spp", "1", "--sweep-depth",
                            "2", "--sweep-min-weight", "0", "--sweep-indirect", "0", "--ref-spp", "4"}),
            0);
        int w = 0, h = 0;
        return readImageRgb8(out + "/reference.png", w, h);
    };
    const auto f0 = run("0"), f0again = run("0"), f3 = run("3");
    EXPECT_EQ(f0, f0again);  // a frame is a pure function of its index
    EXPECT_NE(f0, f3);       // a quarter orbit later the view has changed
    DiskFileSource fs;
    const int frames = anim::Timeline::fromScene(loadScene(scene, fs)).frameCount();
    EXPECT_GE(frames, 10);
    EXPECT_THROW(cli::runReport({scene, "--out", dir, "--frame", std::to_string(frames)}), UsageError);
}

TEST(ReportCli, TheRenderTakesTheReferenceSizeAndRefusesAnother) {
    const std::string dir = testing::freshDir("report_cli_reference");
    const std::string scene = writeScene(dir);  // 24x16 of its own
    const std::string ref = dir + "/ref.png";
    writePng(ref, 30, 20, std::vector<uint8_t>(30 * 20 * 3, 128));
    const std::string out = dir + "/out";
    EXPECT_EQ(
        cli::runReport({scene, "--out", out, "--reference", ref, "--no-video", "--sweep-spp", "1", "--sweep-depth", "2",
                        "--sweep-min-weight", "0", "--sweep-indirect", "0", "--threads", "1"}),
        0);
    int w = 0, h = 0;
    readImageRgb8(out + "/default.png", w, h);
    EXPECT_EQ(w, 30);
    EXPECT_EQ(h, 20);
    const auto csv = readCsv(out + "/report.csv");
    ASSERT_EQ(csv.size(), 1u + 1 + 3);
    for (size_t i = 2; i < csv.size(); ++i) EXPECT_LT(std::stod(cell(csv, i, "ssim")), 1.0);  // grey is no render

    const std::string out2 = dir + "/out2";
    EXPECT_THROW(cli::runReport({scene, "--out", out2, "--reference", ref, "--size", "24x16"}), InputError);
    EXPECT_THROW(cli::runReport({scene, "--out", out2, "--reference", dir + "/none.png"}), InputError);
    EXPECT_THROW(cli::runReport({scene, "--out", out2, "--reference", scene}), InputError);  // not an image
    EXPECT_THROW(cli::runReport({scene, "--out", out2, "--reference", ref, "--ref-spp", "4"}), UsageError);
    EXPECT_THROW(cli::runReport({scene, "--out", out2, "--reference", ref, "--background", "transparent"}),
                 UsageError);
    EXPECT_FALSE(std::filesystem::exists(out2 + "/report.csv"));
}

TEST(ReportCli, RefusesAnUnknownVideoPresetBeforeRendering) {
    const std::string dir = testing::freshDir("report_cli_preset");
    EXPECT_THROW(cli::runReport({writeScene(dir), "--out", dir, "--video-preset", "warp"}), UsageError);
    EXPECT_THROW(cli::runReport({writeScene(dir), "--out", dir, "--video-crf", "52"}), UsageError);
    EXPECT_FALSE(std::filesystem::exists(dir + "/report.csv"));
}

}  // namespace
}  // namespace rf::report
