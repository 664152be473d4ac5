#pragma once
/// The quality report as a whole: reference render, sweep, and the files in the output folder
/// (report.csv, error_vs_time.png/.gp, summary.md, reference.png, default.png, error_default.png).
#include <string>
#include <vector>

#include "report_sweep.h"
#include "scene.h"

namespace rf::report {

struct QualityReportOptions {
    std::string outDir;
    std::string sceneName;  ///< for titles
    int frame = 0;          ///< the frame index the scene is already posed at (seeds samples)
    int threads = 0;        ///< 0: all cores
    double targetPsnr = 30.0;
    SweepSpec sweep;
    QualitySetting reference{256, 16, 0.f};
    bool plot = true;      ///< draw error_vs_time.png with gnuplot
    bool progress = true;  ///< one line per render on stderr
};

struct QualityReport {
    SweepRow reference;
    std::vector<SweepRow> rows;
    std::vector<std::string> rayNotes;
    std::string csvPath, plotPath, summaryPath, errorImagePath, referencePath;
};

/// Renders the reference and the sweep of `scene` (posed at options.frame, settings giving the
/// image size and tone mapping) and writes every file. Throws std::runtime_error on I/O failure.
QualityReport runQualityReport(const Scene& scene, const RenderSettings& settings, const QualityReportOptions& options);

}  // namespace rf::report
