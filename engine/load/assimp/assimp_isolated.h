#pragma once
/// assimp's importers run in a child process. They are a large body of C++ that rayfarm cannot
/// fix: fuzzing found inputs on which Debian's libassimp 5.2 frees a buffer twice (FBX), aborts
/// (3MF), loops for minutes (PLY) or allocates gigabytes for a few bytes (COLLADA). In the child
/// such a file costs the child; rayfarm refuses the file with one line and goes on (the viewer
/// stays open, a farm's rank 0 reports it). The child reads and post-processes the file, then
/// hands the scene back in assimp's own binary dump format (assbin), which the parent reads
/// with assimp's assbin reader: a format only rayfarm writes, from a scene assimp validated.
///
/// Limits on the child, both linear in the file's size: its memory (RLIMIT_DATA: kMemoryBase +
/// kMemoryPerByte × bytes beyond the data it inherits) and its time (kTimeBase + kTimePerByte ×
/// bytes; RAYFARM_TEST_ASSIMP_SECONDS overrides it for tests and fuzzing). A signal that cancels
/// the load (load_control.h) kills the child at once.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

struct aiScene;
namespace Assimp {
class Importer;
}

namespace rf {

/// What the child says besides the scene: why it failed, and what it read.
struct ChildImportReport {
    std::string importerError;     ///< the importer's error string when it made no scene
    std::string violation;         ///< a side file outside the asset root (ConfinedFs), and why
    std::string violationReason;
    std::string ioError;           ///< a side file that could not be read (too big, not a file)
    /// The files the importer read (path, byte limit): the parent reads them again through
    /// its FileSource, so that they travel in the farm's bundle as an in-process read did.
    std::vector<std::pair<std::string, uint64_t>> filesRead;
};

struct ChildImportLimits {
    double seconds = 0.0;     ///< wall time; 0: from the file's size
    uint64_t memoryBytes = 0; ///< beyond the parent's address space; 0: from the file's size
    static constexpr double kTimeBase = 30.0, kTimePerByte = 1.0 / (1 << 20);  // 30 s + 1 s per MiB
    static constexpr uint64_t kMemoryBase = 2ull << 30, kMemoryPerByte = 64;  // 2 GiB + 64 B per byte
};

/// Runs read (ReadFile and post-processing on an importer of its own, filling report) in a child
/// process, then reads the scene it made into `into` (a fresh importer that owns it; nothing is
/// post-processed again). Returns the scene, or nullptr with report.importerError set (or the
/// other fields) as the child's importer left them. Throws InputError(path, …) when the child
/// dies (a crash, the memory limit), runs past its time, or sends something unreadable;
/// LoadCancelled when the load is cancelled. inputBytes: the model file's size, for the limits.
const aiScene* importInChild(Assimp::Importer& into, const std::string& path, uint64_t inputBytes,
                             const std::function<const aiScene*(ChildImportReport&)>& read, ChildImportReport& report,
                             ChildImportLimits limits = {});

/// The parent's side of the message a child sends (what importInChild does with it once read),
/// for tests: a short or malformed message, or one whose counts no message could hold, is an
/// InputError, never a crash or an allocation of its counts.
const aiScene* readChildMessage(Assimp::Importer& into, const std::string& path, const std::string& msg, ChildImportReport& report);

}  // namespace rf
