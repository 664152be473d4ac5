#pragma once
/// Guards between a glTF file and tinygltf: a preflight over the raw bytes (GLB header, glTF
/// version, required extensions, URI confinement, size caps) and file-system callbacks that
/// confine tinygltf to the model's own folder and read through a FileSource. Internal to the
/// glTF loader.
#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/util/file_source.h"

namespace rf::gltf {

/// Caps on what a model may make the loader allocate.
struct Limits {
    static constexpr uint64_t kMaxFileBytes = 2ull << 30;       ///< the .gltf/.glb itself
    static constexpr uint64_t kMaxBufferBytes = 1ull << 30;     ///< one buffer (file or data URI)
    static constexpr uint64_t kMaxDataUriChars = 512ull << 20;  ///< one base64 data URI
    static constexpr uint64_t kMaxImageBytes = 256ull << 20;    ///< one encoded image
    static constexpr int kMaxImageSide = 16384;                 ///< decoded width or height
    static constexpr uint64_t kMaxAccessorCount = 1ull << 26;   ///< elements of one accessor
    /// Elements of an accessor without a bufferView (zeros, maybe sparse): nothing on disk
    /// bounds them, so a few bytes of JSON could otherwise ask for gigabytes.
    static constexpr uint64_t kMaxViewlessCount = 1ull << 22;
    /// Triangles of one model after instancing: many nodes sharing a big mesh multiply it.
    static constexpr uint64_t kMaxTriangles = 1ull << 25;
};

/// Percent-decodes a URI the way tinygltf does before it opens a file.
std::string decodeUri(const std::string& uri);

/// Why a (decoded) external URI may not be opened, or "" if it is a relative path: no absolute
/// path, no scheme, no shell syntax. ".." is allowed here; ConfinedFs keeps the resolved path
/// inside the asset root.
std::string uriProblem(const std::string& decodedUri);

/// The folder a model's relative URIs must stay inside: `root` when given, else the current
/// directory when the model lies under it, else the model's own folder. Symbolic links
/// resolved (weakly_canonical); the model's own folder when nothing can be resolved.
std::string assetRootFor(const std::string& modelPath, const std::string& root);

/// What the preflight learnt about the file.
struct PreflightResult {
    bool binary = false;
    std::vector<std::string> notes;
    /// The document tinygltf must read instead of the file's, when non-empty (patchedFile()).
    std::string patchedJson;
    /// The file's bytes with patchedJson in place of its JSON (a GLB keeps its BIN chunk).
    std::string patchedFile(const std::string& bytes) const;
};

/// Checks the raw file before tinygltf parses it; throws InputError(path, …) on a glTF 1.0 file,
/// a malformed GLB header, invalid JSON, an unsupported required extension, a URI that leaves
/// the folder, or a buffer or data URI over the caps.
/// The glTF extensions whose effect rayfarm renders: a file may require them (others are
/// refused by preflight), and using them draws no "ignored" note. The one list of them.
bool isSupportedExtension(const std::string& name);

PreflightResult preflight(const std::string& path, const std::string& bytes);

/// tinygltf file-system callbacks that resolve URIs against the model's `folder`, open only
/// files whose real path (symbolic links resolved) lies inside `root`, and read them through a
/// FileSource (so worker ranks can load from an in-memory bundle). No shell expansion. Data URIs
/// of any MIME type that tinygltf does not decode itself are decoded here (gltf_images.h).
class ConfinedFs {
public:
    ConfinedFs(FileSource& fs, std::string folder, std::string root);
    tinygltf::FsCallbacks callbacks();
    /// First URI refused by the callbacks (empty if none) and why: the load must then fail.
    const std::string& violation() const { return violation_; }
    const std::string& violationReason() const { return violationReason_; }
    const std::string& root() const { return root_; }
    const std::string& folder() const { return folder_; }
    /// A relative path resolved against the folder as a URI is: the joined path, or "" when it
    /// is refused (violation() then says why). Other loaders' side files (an OBJ's MTL and
    /// textures) go through this too.
    std::string resolve(const std::string& relative) { return expandFilePath(folder_ + "/" + relative, this); }

private:
    static bool fileExists(const std::string& path, void* self);
    static std::string expandFilePath(const std::string& path, void* self);
    static bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self);
    static bool writeWholeFile(std::string* err, const std::string& path, const std::vector<unsigned char>& data, void* self);

    FileSource& fs_;
    std::string folder_;
    std::string root_;
    std::string violation_, violationReason_;
};

/// tinygltf image callback that keeps the encoded bytes instead of decoding them, so only
/// images some used material needs are decoded later (see gltf_materials.h). Images stored in a
/// bufferView are not touched here: tinygltf does not bound-check that view, the decoder does.
bool keepEncodedImage(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                      int reqHeight, const unsigned char* bytes, int size, void* user);

}  // namespace rf::gltf
