#include "engine/load/gltf/gltf_safety.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_images.h"
#include "engine/util/json_guard.h"

namespace rf::gltf {

namespace {

using json = nlohmann::json;

uint32_t readU32(const std::string& b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;  // GLB is little-endian, as every host rayfarm targets
}

bool isDataUri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

void checkUri(const std::string& path, const json& obj, const std::string& where) {
    if (!obj.is_object() || !obj.contains("uri")) return;
    const json& u = obj["uri"];
    if (!u.is_string()) throw InputError(path, where + ".uri: expected a string");
    const std::string uri = u.get<std::string>();
    if (isDataUri(uri)) {
        if (uri.size() > Limits::kMaxDataUriChars)
            throw InputError(path, where + ".uri: data URI of " + std::to_string(uri.size()) +
                                       " characters is over the limit of " + std::to_string(Limits::kMaxDataUriChars));
        return;
    }
    const std::string problem = uriProblem(decodeUri(uri));
    if (!problem.empty()) throw InputError(path, where + ".uri \"" + uri + "\": " + problem);
}

[[noreturn]] void refuseGltf1(const std::string& path, const std::string& why) {
    throw InputError(path, "this is a glTF 1.0 file (" + why + "); rayfarm reads glTF 2.0 only — convert it, e.g. with the glTF 1.0→2.0 converter or Blender");
}

}  // namespace

std::string decodeUri(const std::string& uri) {
    std::string out;
    out.reserve(uri.size());
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else if (uri[i] == '+') {
            out += ' ';  // as tinygltf's urldecode does
        } else {
            out += uri[i];
        }
    }
    return out;
}

namespace {

/// The message for a character of shell syntax, whole, "" for any other character. Each is one
/// literal: a message grown from pieces around the character (operator+, or push_back and
/// append) is a short string outgrowing its inline buffer, which GCC 12's link-time
/// optimisation misreads as a 61-byte read of 16 bytes (-Wstringop-overread, a false positive).
const char* shellCharacterProblem(unsigned char c) {
    switch (c) {
    case '`': return "character '`' is not allowed in a file URI (no shell syntax)";
    case '$': return "character '$' is not allowed in a file URI (no shell syntax)";
    case '\\': return "character '\\' is not allowed in a file URI (no shell syntax)";
    case '*': return "character '*' is not allowed in a file URI (no shell syntax)";
    case '?': return "character '?' is not allowed in a file URI (no shell syntax)";
    case '{': return "character '{' is not allowed in a file URI (no shell syntax)";
    case '}': return "character '}' is not allowed in a file URI (no shell syntax)";
    default: return "";
    }
}

}  // namespace

std::string uriProblem(const std::string& uri) {
    if (uri.empty()) return "empty URI";
    for (unsigned char c : uri) {
        if (c < 0x20 || c == 0x7f) return "control character in the URI";
        // Never expanded here (no wordexp), but refused so no later tool that might expand
        // them sees a name that reads as a command substitution, variable or glob.
        if (const char* why = shellCharacterProblem(c); *why) return why;
    }
    if (uri[0] == '/')
        return "absolute paths are not allowed; use a path relative to the model inside the asset root (--asset-root)";
    if (uri[0] == '~') return "'~' is not expanded; use a path relative to the model inside the asset root (--asset-root)";
    // A scheme ("file:", "http:", "C:") means something other than a file in the folder.
    const size_t colon = uri.find(':');
    if (colon != std::string::npos && uri.find('/') > colon) return "URI schemes other than data: are not supported";
    return "";
}

namespace {

namespace fsys = std::filesystem;

/// weakly_canonical of an absolute path; the lexical form when the file system cannot say.
fsys::path resolved(const fsys::path& p) {
    std::error_code ec;
    fsys::path r = fsys::weakly_canonical(fsys::absolute(p, ec), ec);
    return ec ? fsys::absolute(p).lexically_normal() : r;
}

bool within(const fsys::path& p, const fsys::path& folder) {
    auto [a, b] = std::mismatch(folder.begin(), folder.end(), p.begin(), p.end());
    (void)b;
    return a == folder.end() || (std::next(a) == folder.end() && a->empty());  // "dir/" ends in ""
}

}  // namespace

std::string assetRootFor(const std::string& modelPath, const std::string& root) {
    if (!root.empty()) return resolved(root).string();
    fsys::path folder = fsys::path(modelPath).parent_path();
    if (folder.empty()) folder = ".";
    const fsys::path f = resolved(folder), cwd = resolved(fsys::current_path());
    return (within(f, cwd) ? cwd : f).string();
}

namespace {

/// The JSON chunk of a GLB container, after checking its header and chunk lengths.
std::string glbJsonChunk(const std::string& path, const std::string& bytes) {
    if (bytes.size() < 20) throw InputError(path, "truncated GLB header");
    const uint32_t version = readU32(bytes, 4);
    if (version == 1) refuseGltf1(path, "GLB container version 1");
    if (version != 2) throw InputError(path, "unsupported GLB container version " + std::to_string(version));
    const uint32_t length = readU32(bytes, 8);
    if (length > bytes.size()) throw InputError(path, "GLB header says " + std::to_string(length) + " bytes, file has " + std::to_string(bytes.size()));
    const uint32_t chunkLen = readU32(bytes, 12), chunkType = readU32(bytes, 16);
    if (chunkType != 0x4E4F534Au) throw InputError(path, "first GLB chunk is not JSON");
    // Else the JSON's own bytes would be read as the BIN chunk's header below.
    if (chunkLen == 0) throw InputError(path, "GLB JSON chunk is empty (its length is 0)");
    if (uint64_t(chunkLen) + 20 > length) throw InputError(path, "GLB JSON chunk runs past the end of the file");
    const uint64_t next = 20 + uint64_t(chunkLen);
    if (next < length) {
        if (next + 8 > length) throw InputError(path, "truncated GLB BIN chunk header");
        const uint32_t binLen = readU32(bytes, size_t(next));
        if (next + 8 + binLen > length) throw InputError(path, "GLB BIN chunk runs past the end of the file");
    }
    return bytes.substr(20, chunkLen);
}

/// The top-level checks on the parsed document: version, required extensions, buffer sizes, URIs.
void checkDocument(const std::string& path, const json& doc) {
    // glTF 1.0 keeps its arrays as dictionaries and often says version "1.0" (or a number).
    if (doc.contains("asset") && doc["asset"].is_object() && doc["asset"].contains("version")) {
        const json& v = doc["asset"]["version"];
        const std::string vs = v.is_string() ? v.get<std::string>() : v.dump();
        if (vs.rfind("1", 0) == 0) refuseGltf1(path, "asset.version " + vs);
        if (vs.rfind("2.", 0) != 0) throw InputError(path, "asset.version " + vs + ": rayfarm reads glTF 2.0 only");
    } else {
        for (const char* key : {"accessors", "meshes", "nodes", "buffers"})
            if (doc.contains(key) && doc[key].is_object()) refuseGltf1(path, std::string("\"") + key + "\" is a dictionary");
        throw InputError(path, "asset.version is missing (required by glTF 2.0)");
    }

    if (doc.contains("extensionsRequired") && doc["extensionsRequired"].is_array()) {
        for (const json& e : doc["extensionsRequired"]) {
            if (!e.is_string()) continue;
            const std::string name = e.get<std::string>();
            if (!isSupportedExtension(name))
                throw InputError(path, "requires extension " + name + ", which rayfarm does not support");
        }
    }
    if (doc.contains("buffers") && doc["buffers"].is_array()) {
        const json& bs = doc["buffers"];
        for (size_t i = 0; i < bs.size(); ++i) {
            const std::string w = "buffers[" + std::to_string(i) + "]";
            if (bs[i].is_object() && bs[i].contains("byteLength") && bs[i]["byteLength"].is_number()) {
                const double n = bs[i]["byteLength"].get<double>();
                if (!(n >= 0.0) || n > double(Limits::kMaxBufferBytes))
                    throw InputError(path, w + ".byteLength: " + bs[i]["byteLength"].dump() + " is over the limit of " +
                                               std::to_string(Limits::kMaxBufferBytes) + " bytes");
            }
            checkUri(path, bs[i], w);
        }
    }
    if (doc.contains("images") && doc["images"].is_array()) {
        const json& is = doc["images"];
        for (size_t i = 0; i < is.size(); ++i) checkUri(path, is[i], "images[" + std::to_string(i) + "]");
    }
}

}  // namespace

bool isSupportedExtension(const std::string& name) {
    static const std::set<std::string> s = {"KHR_texture_transform", "KHR_materials_emissive_strength",
                                            "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_specular",
                                            "KHR_lights_punctual", "KHR_mesh_quantization", "EXT_texture_webp", "KHR_materials_unlit",
                                            "KHR_materials_clearcoat", "KHR_draco_mesh_compression",
                                            "KHR_materials_pbrSpecularGlossiness", "KHR_materials_sheen", "KHR_materials_volume",
                                            "KHR_materials_iridescence", "KHR_materials_dispersion",
                                            "KHR_materials_variants",
                                            "EXT_meshopt_compression", "KHR_meshopt_compression",
                                            "KHR_texture_basisu", "KHR_node_visibility", "KHR_animation_pointer",
                                            "EXT_mesh_gpu_instancing"};
    return s.count(name) != 0;
}

namespace {

/// tinygltf refuses an index accessor without a bufferView, which a Draco primitive's indices
/// (in the compressed data) need not have: point it at the Draco bufferView, which the decoder
/// replaces (gltf_compression.h) before anything reads it. True when the document changed.
bool patchDracoIndices(json& doc) {
    if (!doc.contains("meshes") || !doc["meshes"].is_array() || !doc.contains("accessors") || !doc["accessors"].is_array()) return false;
    json& accessors = doc["accessors"];
    bool changed = false;
    for (json& mesh : doc["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (json& p : mesh["primitives"]) {
            if (!p.is_object() || !p.contains("indices") || !p["indices"].is_number_unsigned()) continue;
            if (!p.contains("extensions") || !p["extensions"].is_object()) continue;
            const json& ext = p["extensions"];
            if (!ext.contains("KHR_draco_mesh_compression") || !ext["KHR_draco_mesh_compression"].is_object()) continue;
            const json& d = ext["KHR_draco_mesh_compression"];
            if (!d.contains("bufferView") || !d["bufferView"].is_number_unsigned()) continue;
            const size_t i = p["indices"].get<size_t>();
            if (i >= accessors.size() || !accessors[i].is_object() || accessors[i].contains("bufferView")) continue;
            accessors[i]["bufferView"] = d["bufferView"];
            changed = true;
        }
    }
    return changed;
}

/// A meshopt fallback buffer (EXT_/KHR_meshopt_compression "fallback": true) has no data of its
/// own, which tinygltf cannot take (in a GLB it would read the BIN chunk): give it one byte.
/// Every view on it is compressed and gets a decoded buffer; a view that is not, fails its
/// bounds check. True when the document changed.
bool patchMeshoptFallbacks(json& doc) {
    if (!doc.contains("buffers") || !doc["buffers"].is_array()) return false;
    bool changed = false;
    for (json& b : doc["buffers"]) {
        if (!b.is_object() || b.contains("uri") || !b.contains("extensions") || !b["extensions"].is_object()) continue;
        for (const char* name : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
            const json& e = b["extensions"];
            if (e.contains(name) && e[name].is_object() && e[name].value("fallback", false)) {
                b["uri"] = "data:application/octet-stream;base64,AA==";
                b["byteLength"] = 1;
                changed = true;
                break;
            }
        }
    }
    return changed;
}

/// KHR_animation_pointer's channels have a target without a node, which this tinygltf drops
/// silently (it requires target.node); give each one node −1, which it keeps, so the channel
/// reaches the loader (GltfModel::readAnimations reads its pointer). Whether it patched any.
bool patchPointerChannels(json& doc) {
    bool patched = false;
    if (!doc.contains("animations") || !doc["animations"].is_array()) return false;
    for (json& a : doc["animations"]) {
        if (!a.is_object() || !a.contains("channels") || !a["channels"].is_array()) continue;
        for (json& c : a["channels"]) {
            if (!c.is_object() || !c.contains("target") || !c["target"].is_object()) continue;
            json& t = c["target"];
            if (!t.contains("node") && t.contains("path") && t["path"] == "pointer") {
                t["node"] = -1;
                patched = true;
            }
        }
    }
    return patched;
}

}  // namespace

std::string PreflightResult::patchedFile(const std::string& bytes) const {
    if (!binary) return patchedJson;
    std::string json = patchedJson;
    while (json.size() % 4) json += ' ';
    const uint32_t oldLen = readU32(bytes, 12);
    const std::string rest = bytes.substr(20 + size_t(oldLen));
    std::string out = bytes.substr(0, 12);
    auto putU32 = [&](std::string& s, size_t at, uint32_t v) { std::memcpy(&s[at], &v, 4); };
    out += std::string(8, '\0');
    putU32(out, 12, uint32_t(json.size()));
    putU32(out, 16, 0x4E4F534Au);
    out += json;
    out += rest;
    putU32(out, 8, uint32_t(out.size()));
    return out;
}

PreflightResult preflight(const std::string& path, const std::string& bytes) {
    PreflightResult r;
    r.binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    const std::string jsonText = r.binary ? glbJsonChunk(path, bytes) : bytes;

    // tinygltf parses `extras` recursively: refuse deep nesting before it (or anyone) recurses.
    if (std::string p = jsonDepthProblem(jsonText); !p.empty()) throw InputError(path, p);
    json doc;
    try {
        doc = json::parse(jsonText);
    } catch (const json::exception& e) {
        throw InputError(path, std::string("not valid glTF JSON: ") + e.what());
    }
    if (!doc.is_object()) throw InputError(path, "not valid glTF: the top level is not a JSON object");
    if (std::string d = duplicateJsonKey(jsonText); !d.empty())
        r.notes.push_back(d + ": duplicate JSON key; tinygltf keeps one of them");

    checkDocument(path, doc);
    const bool draco = patchDracoIndices(doc), meshopt = patchMeshoptFallbacks(doc), pointers = patchPointerChannels(doc);
    if (draco || meshopt || pointers) r.patchedJson = doc.dump();
    return r;
}

ConfinedFs::ConfinedFs(FileSource& fs, std::string folder, std::string root)
    : fs_(fs), folder_(std::move(folder)), root_(std::move(root)) {
    if (folder_.empty()) folder_ = ".";
}

tinygltf::FsCallbacks ConfinedFs::callbacks() {
    tinygltf::FsCallbacks cb{};
    cb.FileExists = &ConfinedFs::fileExists;
    cb.ExpandFilePath = &ConfinedFs::expandFilePath;
    cb.ReadWholeFile = &ConfinedFs::readWholeFile;
    cb.WriteWholeFile = &ConfinedFs::writeWholeFile;
    cb.user_data = this;
    return cb;
}

bool ConfinedFs::fileExists(const std::string& path, void* self) {
    auto* me = static_cast<ConfinedFs*>(self);
    if (isDataUri(path)) return true;  // decoded by readWholeFile
    return !path.empty() && me->fs_.exists(path);
}

// tinygltf joins its base dir (which we set to the model's folder) with the decoded URI, and
// also tries "./" + URI against the process's working directory. Only the first is allowed; the
// URI part is re-checked here so nothing the preflight missed can leave the asset root, and the
// file's real path (links resolved, where the FileSource knows the disk) must stay inside it.
// Unlike tinygltf's default this never calls wordexp(), so no shell expansion takes place.
std::string ConfinedFs::expandFilePath(const std::string& path, void* self) {
    auto* me = static_cast<ConfinedFs*>(self);
    const std::string prefix = me->folder_ + "/";
    if (path.compare(0, prefix.size(), prefix) != 0) return "";
    const std::string rel = path.substr(prefix.size());
    // A data URI tinygltf does not know (image/webp, image/ktx2, ...): decoded on read.
    if (isDataUri(rel)) return rel;
    auto refuse = [&](const std::string& why) {
        if (me->violation_.empty()) me->violation_ = rel, me->violationReason_ = why;
        return std::string();
    };
    if (const std::string p = uriProblem(rel); !p.empty()) return refuse(p);
    const std::string joined = (fsys::path(me->folder_) / rel).lexically_normal().string();
    const std::optional<std::string> real = me->fs_.realPath(joined);
    const std::optional<std::string> root = me->fs_.realPath(me->root_);
    if (real && root && !within(fsys::path(*real), fsys::path(*root)))
        return refuse("resolves to " + *real + ", outside the asset root " + *root +
                      " (--asset-root, or the scene file's \"asset_root\", widens it)");
    return joined;
}

bool ConfinedFs::readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* self) {
    auto* me = static_cast<ConfinedFs*>(self);
    if (path.empty()) return false;
    try {
        if (isDataUri(path)) {
            // tinygltf URL-decoded it first, turning base64's '+' into ' ' (never base64 itself).
            std::string uri = path;
            if (uri.find(";base64,") != std::string::npos) std::replace(uri.begin(), uri.end(), ' ', '+');
            std::string why;
            const std::optional<std::string> data = decodeDataUri(uri, nullptr, &why);
            if (!data) throw std::runtime_error(why);
            out->assign(data->begin(), data->end());
            return true;
        }
        const std::string data = me->fs_.read(path, Limits::kMaxBufferBytes);
        out->assign(data.begin(), data.end());
        return true;
    } catch (const std::exception& e) {
        if (err) *err += e.what();
        return false;
    }
}

bool ConfinedFs::writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "rayfarm never writes glTF files";
    return false;
}

bool keepEncodedImage(tinygltf::Image* image, const int, std::string* err, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView >= 0) return true;  // extracted with bounds checks when decoded
    if (size < 0 || uint64_t(size) > Limits::kMaxImageBytes) {
        if (err) *err += "image over the size limit\n";
        return false;
    }
    image->image.assign(bytes, bytes + size);
    image->width = image->height = -1;  // still encoded
    return true;
}

}  // namespace rf::gltf
