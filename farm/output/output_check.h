#pragma once
/// Output paths are checked before any rendering starts, so a long run never ends in an
/// unwritable file.
#include <string>

namespace rf {

/// Throws UsageError ("PATH: cannot write: reason") unless path can be created or
/// overwritten. Leaves no file behind that was not there before.
void checkWritableFile(const std::string& path);

/// Creates the directory (and parents) if needed; throws UsageError if it cannot.
void ensureWritableDir(const std::string& dir);

}  // namespace rf
