// rayfarm render: placeholder until the farm issue lands.
#include "cli.h"

namespace rf::cli {
int runRender(const std::vector<std::string>&) { throw std::runtime_error("render: the MPI farm is not built yet"); }
}  // namespace rf::cli
