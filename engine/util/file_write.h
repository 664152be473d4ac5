#pragma once
/// Output files written so that every failure is seen: a full disk, /dev/full, a quota or an
/// I/O error at close turns into an error naming the file and the OS's reason, never a
/// "wrote" message over an empty file.
#include <string>
#include <string_view>

namespace rf {

/// Writes `bytes` to `path` (created or truncated). With `sync`, waits until the data is on
/// disk (fsync), which also catches write-back errors of file systems that report late.
/// Throws std::runtime_error("PATH: cannot write: REASON").
void writeFileChecked(const std::string& path, std::string_view bytes, bool sync = true);

}  // namespace rf
