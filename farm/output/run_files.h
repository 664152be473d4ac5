#pragma once
/// The files a render writes or reads for itself beside its outputs (the locks, the remux's and
/// the GIF's temporary files, the frames folder's frames, manifest, checksum list and log), so
/// that no output can be named after one of them.
#include <string>
#include <vector>

#include "farm/output/output_paths.h"

namespace rf::farm {

/// What the run's own file at `path` is, in a few words ("the lock this run holds on -o
/// (out.mp4)", "a frame kept in the frames folder out.frames"), "" when path is none of them.
/// video: the run's -o; framesDir: its frames folder ("" with --no-frames).
std::string runFileAt(const std::string& path, const std::string& video, const std::string& framesDir);

/// Throws UsageError "PATH: OPTION names WHAT; choose another name" when an output (empty paths
/// skipped) is one of the run's own files. Checked before anything is written or locked.
void checkOutputsAgainstRunFiles(const std::vector<NamedOutput>& outputs, const std::string& video, const std::string& framesDir);

}  // namespace rf::farm
