#pragma once
/// The version `rayfarm --version` prints and the stats file records (`version`): the project's
/// version in CMakeLists.txt.

namespace rf::farm {

/// "0.1", for example.
const char* rayfarmVersion();

}  // namespace rf::farm
