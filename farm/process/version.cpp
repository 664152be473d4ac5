#include "farm/process/version.h"

namespace rf::farm {

// RAYFARM_VERSION is defined for this one file only (farm/process/CMakeLists.txt), so a new
// version rebuilds one file.
const char* rayfarmVersion() { return RAYFARM_VERSION; }

}  // namespace rf::farm
