#pragma once
/// Output paths are checked before any rendering starts, so a long run never ends in an
/// unwritable file.
#include <functional>
#include <string>

namespace rf {

/// Creates the folder path is in (and its parents) when it is missing, as Blender does; throws
/// UsageError "FOLDER: cannot create the folder for PATH: reason" when it cannot.
void ensureParentDir(const std::string& path);

/// Throws UsageError ("PATH: cannot write: reason") unless path can be created or
/// overwritten; its folder is created first (ensureParentDir). A directory, a FIFO (opening it
/// would wait for a reader) and a socket are refused without being opened. Leaves no file behind
/// that was not there before (folders it made stay, for the run to write into).
void checkWritableFile(const std::string& path);

/// Creates the directory (and parents) if needed; throws UsageError if it cannot.
void ensureWritableDir(const std::string& dir);

/// Writes a whole file so that a failed write (a full disk, `ulimit -f`, a signal) leaves no
/// partial file at `path`: `write` is called with a temporary name beside it (PATH.part-PID),
/// which is renamed over path once written; on failure the temporary file is removed and the
/// error rethrown naming path. A path that exists and is not a regular file (a device such as
/// /dev/full, a pipe) is written in place: renaming over it would replace it.
void writeReplacing(const std::string& path, const std::function<void(const std::string& writeTo)>& write);

}  // namespace rf
