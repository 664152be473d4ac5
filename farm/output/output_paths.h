#pragma once
/// Outputs checked against the run's inputs and against each other before any work starts, so
/// that `-o scene.json` or `--stats out.mp4` is refused instead of overwriting what it names.
#include <string>
#include <vector>

namespace rf {

/// An output by the option that names it ("-o", "--stats", "--frames-dir", ...).
struct NamedOutput {
    std::string option;
    std::string path;
};

/// Whether a and b name the same file: the same inode when both exist (hard links and symlinks
/// included), else the same absolute path once the symlinks of its existing part are resolved.
bool samePath(const std::string& a, const std::string& b);

/// Throws UsageError "PATH: OPTION names ..." when an output (empty paths are skipped) is the
/// same file as another output or as one of `inputs` (the scene file, the model and its
/// buffers and textures, the environment: every file the run reads).
void checkOutputPaths(const std::vector<NamedOutput>& outputs, const std::vector<std::string>& inputs);

}  // namespace rf
