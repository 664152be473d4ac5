#pragma once
/// rayfarm view: the live window; only in builds that found Qt 6.
#include <string>
#include <vector>

namespace rf::cli {

int runView(const std::vector<std::string>& args);

}  // namespace rf::cli
