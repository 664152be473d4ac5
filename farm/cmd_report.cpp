// rayfarm report: placeholder until the report issue lands.
#include "cli.h"

namespace rf::cli {
int runReport(const std::vector<std::string>&) { throw std::runtime_error("report: not built yet"); }
}  // namespace rf::cli
