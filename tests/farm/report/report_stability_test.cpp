// rayfarm report --stability: the cases run, pass, and the naive contrasts really differ.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "farm/report/report_stability.h"
#include "tests/farm/report/report_test_scene.h"

namespace rf::report {
namespace {

TEST(ReportStability, EveryCountedCasePassesAndTheTableHasEveryCase) {
    const std::string dir = testing::freshDir("report_stability");
    const StabilityReport rep = runStabilityReport(dir, 2);
    ASSERT_GE(rep.cases.size(), 10u);
    for (const StabilityCase& c : rep.cases) {
        if (!c.informative) {
            EXPECT_TRUE(c.pass) << "#" << c.id << " " << c.name << ": " << c.measured;
        }
    }
    EXPECT_EQ(rep.passed(), rep.counted());

    std::ifstream csv(rep.csvPath);
    std::string line;
    size_t lines = 0;
    while (std::getline(csv, line)) ++lines;
    EXPECT_EQ(lines, rep.cases.size() + 1);
    std::ifstream md(rep.markdownPath);
    const std::string text(std::istreambuf_iterator<char>(md), {});
    size_t rows = 0;
    for (size_t p = text.find("\n| "); p != std::string::npos; p = text.find("\n| ", p + 1)) ++rows;
    EXPECT_EQ(rows, rep.cases.size() + 1);  // the header row too
}

TEST(ReportStability, CoversTheCataloguesMeasurableCases) {
    std::vector<StabilityCase> cases;
    runTimelineCases(cases);
    std::set<std::string> ids;
    for (const StabilityCase& c : cases) ids.insert(c.id);
    EXPECT_EQ(ids, (std::set<std::string>{"23", "24", "25", "26", "27", "28", "29"}));
    const std::string md = stabilityMarkdown({{"1", "a | b", "x", 0.0, 1.0, "", true, false}});
    EXPECT_NE(md.find("a \\| b"), std::string::npos) << md;  // a pipe may not split the row
}

TEST(ReportStability, NaiveContrastsShowTheErrorTheyExistToShow) {
    // If the naive rows measured no error, the cases could not tell a broken engine from a good one.
    const auto cases = runStabilityCases(2);
    int naive = 0;
    for (const StabilityCase& c : cases) {
        if (!c.informative) continue;
        ++naive;
        EXPECT_GT(c.error, 0.0) << c.name << ": " << c.measured;
    }
    EXPECT_GE(naive, 2);
}

}  // namespace
}  // namespace rf::report
