#pragma once
/// rayfarm report: error against run time for the quality settings, the video sweep, and the
/// stability table.
#include <string>
#include <vector>

namespace rf::cli {

int runReport(const std::vector<std::string>& args);

}  // namespace rf::cli
