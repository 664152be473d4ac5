#pragma once
/// report.csv: one row per render of the quality report, the reference first.
#include <string>
#include <vector>

#include "farm/report/report_sweep.h"

namespace rf::report {

/// A number for CSV and Markdown tables: `digits` significant digits; "inf", "-inf", "nan".
std::string formatNumber(double v, int digits = 6);

/// The header line (no newline), column names in order.
std::string csvHeader();

/// One row as a CSV line (no newline). PSNR of an exact match is written as "inf".
std::string csvLine(const SweepRow& row);

/// Writes the header, the reference row, then every sweep row; throws std::runtime_error naming
/// the path if it cannot be written.
void writeReportCsv(const std::string& path, const SweepRow& reference, const std::vector<SweepRow>& rows);

}  // namespace rf::report
