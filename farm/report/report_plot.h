#pragma once
/// The log-log plot of error against run time, drawn by gnuplot (Debian's gnuplot-nox, whose
/// pngcairo terminal writes PNG). The script is kept beside the PNG so the plot can be re-drawn
/// or restyled by hand.
#include <string>
#include <vector>

#include "farm/report/report_sweep.h"

namespace rf::report {

/// s as a gnuplot string literal (double quotes, escaped).
std::string gnuplotQuote(const std::string& s);

/// Full path of an executable named `name` on PATH, or "" if there is none.
std::string findOnPath(const std::string& name);

/// The gnuplot script: RMSE (left axis, log) and PSNR (right axis) against seconds (log), one
/// point style per sweep line, the Pareto front as a line, the default setting ringed.
std::string gnuplotScript(const std::vector<SweepRow>& rows, const std::string& title, const std::string& pngPath);

/// Writes script to scriptPath and runs gnuplot on it; the script must write pngPath. Throws
/// std::runtime_error if gnuplot is missing, fails, or leaves no PNG.
void runGnuplot(const std::string& script, const std::string& scriptPath, const std::string& pngPath);

/// Writes scriptPath and runs gnuplot on it to make pngPath. Throws std::runtime_error if gnuplot
/// is missing or fails (its stderr goes to ours).
void plotErrorVsTime(const std::vector<SweepRow>& rows, const std::string& title, const std::string& scriptPath,
                     const std::string& pngPath);

}  // namespace rf::report
