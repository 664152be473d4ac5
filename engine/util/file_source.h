#pragma once
/// Where loaders get file bytes from. Rank 0 reads the disk and records every file it read into
/// a bundle; the bundle is broadcast once and the other ranks load the same scene from memory,
/// never touching the scene files themselves.
#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace rf {

/// What lies at path when it is not a regular file, for a message: "a directory", "a FIFO",
/// "a socket", "a device", and without followLinks "a symbolic link"; "" when it is a regular
/// file or nothing is there. It never opens the file (a FIFO would block).
std::string notRegularFile(const std::string& path, bool followLinks = true);

/// Files by path, as read by a loader.
struct FileBundle {
    std::map<std::string, std::string> files;

    /// Flat byte string: count, then (path length, path, size, bytes) per file.
    std::string serialize() const;
    /// Inverse of serialize; throws std::runtime_error on malformed input.
    static FileBundle deserialize(const std::string& bytes);
    size_t totalBytes() const;
};

class FileSource {
public:
    virtual ~FileSource() = default;
    /// Whole file; throws InputError(path, …) if it cannot be read or exceeds maxBytes.
    virtual std::string read(const std::string& path, uint64_t maxBytes = kDefaultMaxBytes) = 0;
    /// Whether anything is at path, a regular file or not: read() says what is wrong with it
    /// (so a FIFO or a folder is reported as one, not as missing).
    virtual bool exists(const std::string& path) = 0;
    /// The path with symbolic links resolved, for confinement checks (gltf_safety.h); nullopt
    /// where no disk answers. Default: the local file system.
    virtual std::optional<std::string> realPath(const std::string& path);
    static constexpr uint64_t kDefaultMaxBytes = 4ull << 30;
};

/// Reads from disk and remembers what it read.
class DiskFileSource : public FileSource {
public:
    std::string read(const std::string& path, uint64_t maxBytes = kDefaultMaxBytes) override;
    bool exists(const std::string& path) override;
    const FileBundle& bundle() const { return bundle_; }

private:
    FileBundle bundle_;
};

/// Serves only what a bundle holds.
class BundleFileSource : public FileSource {
public:
    explicit BundleFileSource(FileBundle bundle) : bundle_(std::move(bundle)) {}
    /// Files that came later; a path already held keeps its bytes.
    void add(FileBundle more) { bundle_.files.merge(more.files); }
    size_t bundleBytes() const { return bundle_.totalBytes(); }
    std::string read(const std::string& path, uint64_t maxBytes = kDefaultMaxBytes) override;
    bool exists(const std::string& path) override;
    /// None: the bundle holds only what rank 0 read, after its own checks.
    std::optional<std::string> realPath(const std::string&) override { return std::nullopt; }

private:
    FileBundle bundle_;
};

}  // namespace rf
