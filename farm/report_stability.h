#pragma once
/// `rayfarm report --stability`: the stiff and extreme cases of the stability catalogue
/// (shared/stability.md) that can be rendered or measured through the engine's API, each with
/// the error measured and a pass/fail against a stated tolerance.
#include <string>
#include <vector>

namespace rf::report {

/// One row of the stability table.
struct StabilityCase {
    std::string id;        ///< number in the catalogue ("21"), so a reader can look up the why
    std::string name;      ///< what was set up
    std::string measured;  ///< the figure, in words ("99.98% of pixels within 1/255")
    double error = 0.0;    ///< the measured error in the unit of tolerance
    double tolerance = 0.0;
    std::string unit;      ///< of error and tolerance
    bool pass = false;
    bool informative = false;  ///< shows what a naive method does: not counted as pass/fail
};

struct StabilityReport {
    std::vector<StabilityCase> cases;
    std::string markdownPath, csvPath;
    int passed() const;
    int counted() const;  ///< cases that are not merely informative
};

/// Every case, in catalogue order. threads: 0 for all cores.
std::vector<StabilityCase> runStabilityCases(int threads);

/// The timeline cases (#23–#29: short-path slerp, slerp edges, turntable yaw, CUBICSPLINE,
/// key rules, Catmull–Rom duplicates, degenerate lookAt), appended to out.
void runTimelineCases(std::vector<StabilityCase>& out);

/// The table as Markdown and as CSV.
std::string stabilityMarkdown(const std::vector<StabilityCase>& cases);
std::string stabilityCsv(const std::vector<StabilityCase>& cases);

/// Runs every case and writes stability.md and stability.csv into outDir.
StabilityReport runStabilityReport(const std::string& outDir, int threads);

}  // namespace rf::report
