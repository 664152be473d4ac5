#pragma once
/// `rayfarm report --stability`: the stiff and extreme cases of the stability catalogue
/// (docs/stability.md) that can be rendered or measured through the engine's API, each with
/// the error measured and a pass/fail against a stated tolerance.
#include <string>
#include <vector>

#include "farm/report/stability/stability_case.h"

namespace rf::report {

/// One row of the stability table (defined with the engine's cases, farm/report/stability/).
using stability::StabilityCase;

struct StabilityReport {
    std::vector<StabilityCase> cases;
    std::string markdownPath, csvPath;
    int passed() const;
    int counted() const;  ///< cases that are not merely informative
};

/// Every case, in catalogue order: the engine's (farm/report/stability/), the timeline's, then the
/// frame times. threads: 0 for all cores.
std::vector<StabilityCase> runStabilityCases(int threads);

/// The timeline cases (#23–#29: short-path slerp, slerp edges, turntable yaw, CUBICSPLINE,
/// key rules, Catmull–Rom duplicates, degenerate lookAt), appended to out.
void runTimelineCases(std::vector<StabilityCase>& out);

/// #30: the time of frame 100000 at 30 fps from its index, with the accumulated sum a naive
/// player computes as an informative contrast.
void frameTimeCases(std::vector<StabilityCase>& out);

/// The table as Markdown and as CSV.
std::string stabilityMarkdown(const std::vector<StabilityCase>& cases);
std::string stabilityCsv(const std::vector<StabilityCase>& cases);

/// Runs every case and writes stability.md and stability.csv into outDir.
StabilityReport runStabilityReport(const std::string& outDir, int threads);

}  // namespace rf::report
