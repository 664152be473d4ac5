#include "engine/load/assimp/assimp_import.h"
#include "engine/load/assimp/assimp_morph.h"
#include "engine/load/assimp/assimp_skin.h"
#include "engine/load/assimp/assimp_textures.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <type_traits>

#include <assimp/Importer.hpp>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/version.h>

#include "engine/load/assimp/assimp_isolated.h"
#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/util/model_path.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/gltf/gltf_safety.h"

namespace rf {

namespace {

static_assert(std::is_same_v<ai_real, float>, "assimp built with double precision: positions are copied as floats");

using gltf::ConfinedFs;
using gltf::Limits;

/// The extensions read through assimp, with the format's name for `info`.
struct Format {
    const char* ext;
    const char* name;
};
constexpr Format kFormats[] = {{".obj", "OBJ"}, {".stl", "STL"}, {".ply", "PLY"},
                               {".fbx", "FBX"}, {".dae", "COLLADA"}, {".3mf", "3MF"}};

/// An assimp stream over bytes read whole through the FileSource.
class StringStream : public Assimp::IOStream {
public:
    explicit StringStream(std::string bytes) : bytes_(std::move(bytes)) {}
    size_t Read(void* buffer, size_t size, size_t count) override {
        if (size == 0 || count == 0) return 0;
        const size_t items = std::min(count, (bytes_.size() - pos_) / size);
        std::memcpy(buffer, bytes_.data() + pos_, items * size);
        pos_ += items * size;
        return items;
    }
    size_t Write(const void*, size_t, size_t) override { return 0; }
    aiReturn Seek(size_t offset, aiOrigin origin) override {
        size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? pos_ : bytes_.size();
        if (offset > bytes_.size() - std::min(base, bytes_.size())) return aiReturn_FAILURE;
        pos_ = base + offset;
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return pos_; }
    size_t FileSize() const override { return bytes_.size(); }
    void Flush() override {}

private:
    std::string bytes_;
    size_t pos_ = 0;
};

/// assimp's file system: the model itself, and side files (an OBJ's MTL, COLLADA's or FBX's
/// external files) only inside the asset root, all read through the FileSource so that they
/// travel in the farm's bundle. Never writes.
class ConfinedIoSystem : public Assimp::IOSystem {
public:
    ConfinedIoSystem(FileSource& fs, std::string model, ConfinedFs& confined) : fs_(fs), model_(std::move(model)), confined_(confined) {}
    bool Exists(const char* file) const override {
        const std::string p = resolve(file);
        return !p.empty() && fs_.exists(p);
    }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        if (!mode || std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+')) return nullptr;
        const std::string p = resolve(file);
        if (p.empty() || !fs_.exists(p)) return nullptr;
        const uint64_t limit = p == model_ ? Limits::kMaxFileBytes : Limits::kMaxBufferBytes;
        try {
            auto* stream = new StringStream(fs_.read(p, limit));
            read_.emplace_back(p, limit);
            return stream;
        } catch (const InputError& e) {
            if (error_.empty()) error_ = e.what();
            return nullptr;
        }
    }
    void Close(Assimp::IOStream* stream) override { delete stream; }
    bool ComparePaths(const char* a, const char* b) const override { return std::strcmp(a, b) == 0; }
    /// A side file that could not be read (too big, not a regular file), as FileSource said.
    const std::string& error() const { return error_; }
    /// The files read (path, byte limit), in order.
    const std::vector<std::pair<std::string, uint64_t>>& filesRead() const { return read_; }

private:
    /// The model as given; anything else relative to the model's folder, through ConfinedFs
    /// (which notes a refused path as its violation).
    std::string resolve(const char* file) const {
        if (!file || !*file) return "";
        std::string f = file;
        std::replace(f.begin(), f.end(), '\\', '/');
        if (f == model_) return f;
        const std::string prefix = confined_.folder() + "/";
        if (f.compare(0, prefix.size(), prefix) == 0) f = f.substr(prefix.size());
        // A side file named by an absolute path of the machine that wrote the model (an MTL at
        // C:/Users/...; assimp may also join such a name to the model's folder): looked for by
        // its name beside the model, as textures are.
        if (!f.empty() && (f[0] == '/' || (f.size() > 1 && f[1] == ':'))) f = std::filesystem::path(f).filename().string();
        while (f.compare(0, 2, "./") == 0) f = f.substr(2);
        return f.empty() ? f : confined_.resolve(f);
    }

    FileSource& fs_;
    std::string model_;
    ConfinedFs& confined_;
    mutable std::string error_;
    std::vector<std::pair<std::string, uint64_t>> read_;
};

double metaNumber(const aiMetadata* meta, const char* key, double fallback) {
    if (!meta) return fallback;
    for (unsigned i = 0; i < meta->mNumProperties; ++i) {
        if (std::strcmp(meta->mKeys[i].C_Str(), key) != 0) continue;
        const aiMetadataEntry& e = meta->mValues[i];
        if (!e.mData) return fallback;
        switch (e.mType) {
        case AI_BOOL: return *static_cast<const bool*>(e.mData) ? 1.0 : 0.0;
        case AI_INT32: return *static_cast<const int32_t*>(e.mData);
        case AI_UINT64: return double(*static_cast<const uint64_t*>(e.mData));
        case AI_FLOAT: return *static_cast<const float*>(e.mData);
        case AI_DOUBLE: return *static_cast<const double*>(e.mData);
        default: return fallback;
        }
    }
    return fallback;
}

/// Row-major 3×3 basis and a scale: model space to glTF's (Y up, +Z to the front, metres).
struct AxisConversion {
    double rows[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double scale = 1.0;
    std::string note;  ///< how the file's axes were read, for the notes ("" when Y-up metres)
};

AxisConversion axisConversion(const std::string& ext, const aiScene& scene) {
    AxisConversion c;
    if (ext == ".stl" || ext == ".3mf") {
        // STL has no unit or axes; by convention (slicers, Blender, 3MF's specification) Z is
        // up and a unit is a millimetre.
        c.rows[1][1] = c.rows[2][2] = 0.0;  // (x, y, z) → (x, z, −y)
        c.rows[1][2] = 1.0;
        c.rows[2][1] = -1.0;
        c.scale = 0.001;
    } else if (ext == ".fbx") {
        // FBX names its axes: up, front and "coord" (right), each an axis and a sign, and its unit
        // in centimetres. assimp passes them through as metadata and leaves the data as it is.
        const aiMetadata* m = scene.mMetaData;
        const int up = int(metaNumber(m, "UpAxis", 1)), front = int(metaNumber(m, "FrontAxis", 2)),
                  right = int(metaNumber(m, "CoordAxis", 0));
        const double upSign = metaNumber(m, "UpAxisSign", 1) < 0 ? -1 : 1, frontSign = metaNumber(m, "FrontAxisSign", 1) < 0 ? -1 : 1,
                     rightSign = metaNumber(m, "CoordAxisSign", 1) < 0 ? -1 : 1;
        const bool valid = up >= 0 && up < 3 && front >= 0 && front < 3 && right >= 0 && right < 3 && up != front && up != right &&
                           front != right;
        if (valid) {
            for (auto& r : c.rows) r[0] = r[1] = r[2] = 0;
            c.rows[0][right] = rightSign;
            c.rows[1][up] = upSign;
            c.rows[2][front] = frontSign;
            if (!(up == 1 && upSign > 0 && front == 2 && frontSign > 0 && right == 0 && rightSign > 0))
                c.note = "FBX axes (up " + std::string(upSign < 0 ? "-" : "+") + "XYZ"[up] + ", front " +
                         (frontSign < 0 ? "-" : "+") + "XYZ"[front] + ") turned to glTF's (+Y up)";
        } else {
            c.note = "FBX axis settings unusable (UpAxis " + std::to_string(up) + ", FrontAxis " + std::to_string(front) +
                     ", CoordAxis " + std::to_string(right) + "); taken as Y up";
        }
        const double unit = metaNumber(m, "UnitScaleFactor", 1.0);
        if (std::isfinite(unit) && unit > 0) c.scale = unit / 100.0;
    }
    // COLLADA: assimp applies the file's <up_axis> and <unit meter> itself. OBJ and PLY name
    // neither; both are Y up by the convention of the tools that write them.
    return c;
}

/// sRGB-encoded (as every format here stores colours by the byte) to linear, as glTF's COLOR_0 is.
float srgbToLinear(float v) {
    if (!(v > 0.f)) return 0.f;
    if (v >= 1.f) return 1.f;
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

/// Builds the glTF model: one buffer, a view and accessor per attribute.
class GltfWriter {
public:
    GltfWriter(const std::string& path, FileSource& fs, ConfinedFs& confined, std::vector<std::string>& notes)
        : path_(path), fs_(fs), confined_(confined), notes_(notes) {
        model_.buffers.emplace_back();
        model_.asset.version = "2.0";
    }

    tinygltf::Model take() { return std::move(model_); }
    tinygltf::Model& model() { return model_; }

    void reserve(size_t bytes) { model_.buffers[0].data.reserve(bytes); }

    int view(const void* data, size_t bytes, int target) {
        std::vector<unsigned char>& buf = model_.buffers[0].data;
        while (buf.size() % 4) buf.push_back(0);
        tinygltf::BufferView v;
        v.buffer = 0;
        v.byteOffset = buf.size();
        v.byteLength = bytes;
        v.target = target;
        const auto* p = static_cast<const unsigned char*>(data);
        buf.insert(buf.end(), p, p + bytes);
        model_.bufferViews.push_back(v);
        return int(model_.bufferViews.size() - 1);
    }

    int accessor(int view, int componentType, int type, size_t count, std::vector<double> min = {}, std::vector<double> max = {}) {
        tinygltf::Accessor a;
        a.bufferView = view;
        a.componentType = componentType;
        a.type = type;
        a.count = count;
        a.minValues = std::move(min);
        a.maxValues = std::move(max);
        model_.accessors.push_back(std::move(a));
        return int(model_.accessors.size() - 1);
    }

    /// aiMesh → a primitive (attributes and indices made once, shared by every node that draws it).
    /// -1 when the mesh has nothing to draw.
    struct Prim {
        tinygltf::Primitive prim;
        bool ok = false;
    };
    Prim mesh(const aiMesh& m, int material, const AssimpSkin& skin, const AssimpMorph& morph) {
        Prim out;
        const size_t n = m.mNumVertices;
        if (n == 0 || !m.mVertices || m.mNumFaces == 0 || !m.mFaces) return out;
        int mode = TINYGLTF_MODE_TRIANGLES;
        unsigned per = 3;
        // Sorted by type, so never mixed; triangulated polygons carry the n-gon flag beside it.
        const unsigned types = m.mPrimitiveTypes & ~unsigned(aiPrimitiveType_NGONEncodingFlag);
        if (types == aiPrimitiveType_POINT) mode = TINYGLTF_MODE_POINTS, per = 1;
        else if (types == aiPrimitiveType_LINE) mode = TINYGLTF_MODE_LINE, per = 2;
        else if (types != aiPrimitiveType_TRIANGLE) return out;
        std::vector<uint32_t> indices;
        indices.reserve(size_t(m.mNumFaces) * per);
        for (unsigned f = 0; f < m.mNumFaces; ++f) {
            const aiFace& face = m.mFaces[f];
            if (face.mNumIndices != per || !face.mIndices) continue;
            bool inRange = true;
            for (unsigned k = 0; k < per; ++k) inRange = inRange && face.mIndices[k] < n;
            if (!inRange) continue;
            indices.insert(indices.end(), face.mIndices, face.mIndices + per);
        }
        if (indices.empty()) return out;
        // Triangles without normals are drawn flat, as Blender draws a PLY or OBJ without them:
        // each corner its own vertex, carrying its face's normal (the glTF loader would smooth
        // shared vertices). src maps the vertices written to the mesh's own.
        std::vector<uint32_t> src;
        std::vector<aiVector3D> flatPos, flatNormal;
        size_t count = n;
        const aiVector3D* pos = m.mVertices;
        const aiVector3D* normals = m.mNormals;
        if (!normals && mode == TINYGLTF_MODE_TRIANGLES) {
            src.swap(indices);
            count = src.size();
            flatPos.resize(count);
            flatNormal.resize(count);
            indices.resize(count);
            for (size_t i = 0; i < count; i += 3) {
                const aiVector3D &a = m.mVertices[src[i]], &b = m.mVertices[src[i + 1]], &c = m.mVertices[src[i + 2]];
                aiVector3D nrm = (b - a) ^ (c - a);
                const float len = nrm.Length();
                nrm = len > 0.f && std::isfinite(len) ? nrm / len : aiVector3D(0.f);
                for (size_t k = 0; k < 3; ++k) flatPos[i + k] = m.mVertices[src[i + k]], flatNormal[i + k] = nrm, indices[i + k] = uint32_t(i + k);
            }
            pos = flatPos.data();
            normals = flatNormal.data();
        }
        auto from = [&](size_t i) { return src.empty() ? i : size_t(src[i]); };
        if (f32(pos, count, out, "POSITION", true) < 0) return out;
        if (normals) f32(normals, count, out, "NORMAL", false);
        if (m.mTextureCoords[0]) {
            std::vector<float> uv(2 * count);
            for (size_t i = 0; i < count; ++i) uv[2 * i] = m.mTextureCoords[0][from(i)].x, uv[2 * i + 1] = m.mTextureCoords[0][from(i)].y;
            out.prim.attributes["TEXCOORD_0"] = accessor(view(uv.data(), uv.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                                                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, count);
        }
        if (m.mColors[0]) {
            std::vector<float> c(4 * count);
            for (size_t i = 0; i < count; ++i) {
                const aiColor4D& v = m.mColors[0][from(i)];
                c[4 * i] = srgbToLinear(v.r), c[4 * i + 1] = srgbToLinear(v.g), c[4 * i + 2] = srgbToLinear(v.b);
                c[4 * i + 3] = v.a >= 0.f && v.a <= 1.f ? v.a : v.a > 1.f ? 1.f : std::isnan(v.a) ? 1.f : 0.f;
            }
            out.prim.attributes["COLOR_0"] = accessor(view(c.data(), c.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, count);
        }
        for (int set = 0; set < skin.sets; ++set) {
            std::vector<uint16_t> j(4 * count);
            std::vector<float> wt(4 * count);
            const size_t width = size_t(4 * skin.sets);
            for (size_t i = 0; i < count; ++i)
                for (size_t c = 0; c < 4; ++c)
                    j[4 * i + c] = skin.joints[from(i) * width + size_t(4 * set) + c], wt[4 * i + c] = skin.weights[from(i) * width + size_t(4 * set) + c];
            const std::string n = std::to_string(set);
            out.prim.attributes["JOINTS_" + n] = accessor(view(j.data(), j.size() * 2, TINYGLTF_TARGET_ARRAY_BUFFER),
                                                          TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, count);
            out.prim.attributes["WEIGHTS_" + n] = accessor(view(wt.data(), wt.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                                                           TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, count);
        }
        for (size_t t = 0; t < morph.targets(); ++t) {
            std::map<std::string, int>& target = out.prim.targets.emplace_back();
            std::vector<aiVector3D> d(count);
            for (size_t i = 0; i < count; ++i) d[i] = morph.positions[t][from(i)];
            target["POSITION"] = vec3(d.data(), count, true);
            if (morph.normals[t].empty()) continue;
            for (size_t i = 0; i < count; ++i) d[i] = morph.normals[t][from(i)];
            target["NORMAL"] = vec3(d.data(), count, false);
        }
        out.prim.indices = accessor(view(indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
        out.prim.mode = mode;
        out.prim.material = material;
        out.ok = true;
        return out;
    }

    /// An image for a material's texture path, -1 when none can be used (noted). Throws when
    /// the path leaves the asset root.
    int texture(const aiScene& scene, const aiString& raw, const std::string& where) {
        if (raw.length == 0) return -1;
        if (auto it = textures_.find(raw.C_Str()); it != textures_.end()) return it->second;
        std::string label;
        auto bytes = textureBytes(scene, raw, where, label);
        const int index = bytes ? image(std::move(*bytes), label) : -1;
        textures_[raw.C_Str()] = index;
        return index;
    }

    /// The encoded bytes of a material's texture path (embedded, or a file found as assimp's
    /// importers and Blender's look for it), with a label for messages; nullopt when none can be
    /// used (noted). Throws when the path leaves the asset root.
    std::optional<std::vector<unsigned char>> textureBytes(const aiScene& scene, const aiString& raw, const std::string& where,
                                                           std::string& label) {
        std::string name = raw.C_Str();
        if (name.empty()) return std::nullopt;
        if (const aiTexture* t = scene.GetEmbeddedTexture(raw.C_Str())) {
            if (t->mHeight == 0 && t->pcData && t->mWidth > 0 && uint64_t(t->mWidth) <= Limits::kMaxImageBytes) {
                const auto* p = reinterpret_cast<const unsigned char*>(t->pcData);
                label = "embedded " + printable(name);
                return std::vector<unsigned char>(p, p + t->mWidth);
            }
            notes_.push_back(where + ": embedded texture \"" + name + "\" is stored as raw texels, which rayfarm does not read; ignored");
            return std::nullopt;
        }
        std::replace(name.begin(), name.end(), '\\', '/');
        std::string rel = name;
        // Authoring tools write absolute paths of the machine they ran on (C:/Users/...):
        // the file is looked for by its name beside the model, as Blender's importers do.
        const bool absolute = rel[0] == '/' || (rel.size() > 1 && rel[1] == ':');
        if (absolute) rel = std::filesystem::path(rel).filename().string();
        while (rel.compare(0, 2, "./") == 0) rel = rel.substr(2);
        const std::string resolved = rel.empty() ? std::string() : confined_.resolve(rel);
        if (resolved.empty() && !confined_.violation().empty())
            throw InputError(path_, where + ": texture \"" + confined_.violation() + "\": " + confined_.violationReason() + "; refused");
        if (resolved.empty() || !fs_.exists(resolved)) {
            notes_.push_back(where + ": texture \"" + name + "\" not found" + (absolute ? " (looked for " + rel + " beside the model)" : "") +
                             "; ignored");
            return std::nullopt;
        }
        const std::string bytes = fs_.read(resolved, Limits::kMaxImageBytes);
        label = rel;
        return std::vector<unsigned char>(bytes.begin(), bytes.end());
    }

    /// An image made here (two maps combined into the one glTF has), PNG-encoded.
    int madeTexture(std::vector<unsigned char> png, const std::string& label) { return image(std::move(png), label); }

private:
    int image(std::vector<unsigned char> bytes, const std::string& name) {
        tinygltf::Image img;
        img.name = name;
        img.uri = name;
        img.image = std::move(bytes);
        img.width = img.height = -1;  // still encoded, as the glTF loader keeps them (keepEncodedImage)
        model_.images.push_back(std::move(img));
        tinygltf::Texture t;
        t.source = int(model_.images.size() - 1);
        model_.textures.push_back(t);
        return int(model_.textures.size() - 1);
    }

    int f32(const aiVector3D* v, size_t n, Prim& out, const char* attribute, bool bounds) {
        const int a = vec3(v, n, bounds);
        if (a >= 0) out.prim.attributes[attribute] = a;
        return a;
    }

    /// A VEC3 float accessor of v, with its finite bounds if asked (-1 when none is finite).
    int vec3(const aiVector3D* v, size_t n, bool bounds) {
        std::vector<double> lo, hi;
        if (bounds) {
            lo.assign(3, std::numeric_limits<double>::infinity());
            hi.assign(3, -std::numeric_limits<double>::infinity());
            for (size_t i = 0; i < n; ++i) {
                const double p[3] = {v[i].x, v[i].y, v[i].z};
                if (!std::isfinite(p[0] + p[1] + p[2])) continue;  // the loader drops its triangles
                for (int k = 0; k < 3; ++k) lo[size_t(k)] = std::min(lo[size_t(k)], p[k]), hi[size_t(k)] = std::max(hi[size_t(k)], p[k]);
            }
            if (!(lo[0] <= hi[0])) return -1;  // no finite position
        }
        return accessor(view(v, n * sizeof(aiVector3D), TINYGLTF_TARGET_ARRAY_BUFFER), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n,
                        std::move(lo), std::move(hi));
    }

    std::string path_;
    FileSource& fs_;
    ConfinedFs& confined_;
    std::vector<std::string>& notes_;
    tinygltf::Model model_;
    std::map<std::string, int> textures_;
};

bool color(const aiMaterial& m, const char* key, unsigned type, unsigned index, aiColor4D& out) {
    return m.Get(key, type, index, out) == AI_SUCCESS;
}
bool number(const aiMaterial& m, const char* key, unsigned type, unsigned index, float& out) {
    return m.Get(key, type, index, out) == AI_SUCCESS && std::isfinite(out);
}
double clamp01(double v) { return std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0; }

tinygltf::Value numbers(std::initializer_list<double> v) {
    tinygltf::Value::Array a;
    for (double x : v) a.emplace_back(x);
    return tinygltf::Value(std::move(a));
}

/// The file's material as the glTF BRDF: docs/pictures.md, "Models that are not glTF".
tinygltf::Material material(const aiScene& scene, const aiMaterial& m, const std::string& ext, GltfWriter& w,
                            std::vector<std::string>& notes, std::set<std::string>& extensions) {
    tinygltf::Material g;
    aiString name;
    if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS) g.name = name.C_Str();
    const std::string where = "material \"" + printable(g.name) + "\"";
    auto& pbr = g.pbrMetallicRoughness;
    aiColor4D c;
    if (color(m, AI_MATKEY_BASE_COLOR, c) || color(m, AI_MATKEY_COLOR_DIFFUSE, c))
        pbr.baseColorFactor = {clamp01(c.r), clamp01(c.g), clamp01(c.b), 1.0};
    float opacity = 1.f;
    if (number(m, AI_MATKEY_OPACITY, opacity) && opacity < 1.f) {
        pbr.baseColorFactor[3] = clamp01(opacity);
        g.alphaMode = "BLEND";
    }
    float v = 0.f;
    pbr.metallicFactor = number(m, AI_MATKEY_METALLIC_FACTOR, v) ? clamp01(v) : 0.0;
    if (number(m, AI_MATKEY_ROUGHNESS_FACTOR, v)) {
        pbr.roughnessFactor = clamp01(v);
    } else if (number(m, AI_MATKEY_SHININESS, v)) {
        // As Blender 3.4 reads and writes them: an MTL's Ns (0–1000) as 1 − √(Ns / 1000), an
        // FBX's or COLLADA's shininess (0–100) as 1 − √s / 10.
        pbr.roughnessFactor = clamp01(1.0 - std::sqrt(std::max(0.f, v) / (ext == ".obj" ? 1000.0 : 100.0)));
    } else {
        pbr.roughnessFactor = 0.5;
    }
    // The specular level as Blender's importers set Principled's Specular (0.5 being glTF's
    // default F0 of 0.04, specularColorFactor 1): an MTL's Ks or COLLADA's specular colour as it
    // is; FBX's SpecularFactor doubled, its colour left out (Blender's exporter writes the base
    // colour there).
    float fbxSpecular = 0.f;
    const bool fbx = ext == ".fbx" && number(m, AI_MATKEY_SHININESS_STRENGTH, fbxSpecular);
    if (fbx) c = aiColor4D(std::min(1.f, 2.f * std::max(0.f, fbxSpecular)));
    if ((fbx || color(m, AI_MATKEY_COLOR_SPECULAR, c)) && !(ext == ".stl" || ext == ".ply")) {
        tinygltf::Value::Object spec;
        spec["specularColorFactor"] = numbers({2.0 * clamp01(c.r), 2.0 * clamp01(c.g), 2.0 * clamp01(c.b)});
        // A black specular colour (MTL's Ks 0, common in older files) means no specular at all:
        // Blender's Specular 0 leaves none, where specularColorFactor 0 alone keeps glTF's
        // Fresnel rim (F90 stays specularFactor), a pale sheen over dark rough surfaces.
        if (clamp01(c.r) + clamp01(c.g) + clamp01(c.b) == 0.0) spec["specularFactor"] = tinygltf::Value(0.0);
        g.extensions["KHR_materials_specular"] = tinygltf::Value(std::move(spec));
        extensions.insert("KHR_materials_specular");
    }
    if (color(m, AI_MATKEY_COLOR_EMISSIVE, c) && std::isfinite(c.r + c.g + c.b) && c.r + c.g + c.b > 0.f) {
        const double peak = std::max({double(c.r), double(c.g), double(c.b)});
        const double s = peak > 1.0 ? peak : 1.0;
        g.emissiveFactor = {std::max(0.0, c.r / s), std::max(0.0, c.g / s), std::max(0.0, c.b / s)};
        if (s > 1.0) {
            tinygltf::Value::Object strength;
            strength["emissiveStrength"] = tinygltf::Value(s);
            g.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(std::move(strength));
            extensions.insert("KHR_materials_emissive_strength");
        }
    }
    aiString path;
    auto tex = [&](aiTextureType type) -> int {
        if (m.GetTextureCount(type) == 0 || m.GetTexture(type, 0, &path) != AI_SUCCESS) return -1;
        return w.texture(scene, path, where);
    };
    auto texPath = [&](aiTextureType type) -> std::string {
        aiString p;
        return m.GetTextureCount(type) && m.GetTexture(type, 0, &p) == AI_SUCCESS ? std::string(p.C_Str()) : std::string();
    };
    int t = tex(aiTextureType_BASE_COLOR);
    if (t < 0) t = tex(aiTextureType_DIFFUSE);
    pbr.baseColorTexture.index = t;
    // OBJ's map_Bump and bump (assimp's HEIGHT) are normal maps as Blender's importer reads them;
    // an explicit normal map (norm, FBX NormalMap) wins.
    t = tex(aiTextureType_NORMALS);
    if (t < 0 && ext == ".obj") t = tex(aiTextureType_HEIGHT);
    g.normalTexture.index = t;
    if ((t = tex(aiTextureType_EMISSIVE)) >= 0 || (t = tex(aiTextureType_EMISSION_COLOR)) >= 0) {
        g.emissiveTexture.index = t;
        if (g.emissiveFactor == std::vector<double>{0.0, 0.0, 0.0}) g.emissiveFactor = {1.0, 1.0, 1.0};
    }
    // glTF packs roughness in G and metalness in B of one texture. A grey roughness map (map_Pr)
    // works there as it is when metalness is 0 (factor × B = 0); with a metalness map, the two
    // are combined into one (assimp_textures.h). A map stands for its value: the factor then 1,
    // as Blender's importers connect the map in the factor's place.
    const std::string rough = texPath(aiTextureType_DIFFUSE_ROUGHNESS), metal = texPath(aiTextureType_METALNESS);
    using Bytes = std::optional<std::vector<unsigned char>>;
    const Bytes noMap = std::vector<unsigned char>{};  // a map not given: combined without it
    auto bytesOf = [&](aiTextureType type, std::string& label) -> Bytes {
        aiString p;
        if (m.GetTextureCount(type) == 0 || m.GetTexture(type, 0, &p) != AI_SUCCESS) return noMap;
        return w.textureBytes(scene, p, where, label);
    };
    if (!rough.empty() && (metal.empty() || metal == rough) && (pbr.metallicFactor == 0.0 || metal == rough)) {
        pbr.metallicRoughnessTexture.index = tex(aiTextureType_DIFFUSE_ROUGHNESS);
        if (metal.empty()) pbr.roughnessFactor = number(m, AI_MATKEY_ROUGHNESS_FACTOR, v) ? clamp01(v) : 1.0;
    } else if (!rough.empty() || !metal.empty()) {
        std::string roughLabel, metalLabel, why;
        const Bytes r = bytesOf(aiTextureType_DIFFUSE_ROUGHNESS, roughLabel), mt = bytesOf(aiTextureType_METALNESS, metalLabel);
        if (r && mt) {
            if (auto combined = metallicRoughnessMap(*r, *mt, why)) {
                pbr.metallicRoughnessTexture.index = w.madeTexture(std::move(*combined), "metalness " + metalLabel + " and roughness " + roughLabel);
                if (!rough.empty()) pbr.roughnessFactor = 1.0;
                if (!metal.empty()) pbr.metallicFactor = 1.0;
            } else {
                notes.push_back(where + ": metalness and roughness maps not combined (" + why + "); ignored");
            }
        }
    }
    // glTF takes alpha from the base colour texture: a separate opacity map becomes its alpha.
    const std::string opacityMap = texPath(aiTextureType_OPACITY);
    if (!opacityMap.empty() && opacityMap != texPath(aiTextureType_DIFFUSE)) {
        std::string colourLabel, opacityLabel, why;
        const int base = pbr.baseColorTexture.index;
        Bytes colour = noMap;
        if (base >= 0) colour = bytesOf(m.GetTextureCount(aiTextureType_BASE_COLOR) ? aiTextureType_BASE_COLOR : aiTextureType_DIFFUSE, colourLabel);
        const auto opacityBytes = bytesOf(aiTextureType_OPACITY, opacityLabel);
        if (colour && opacityBytes) {
            if (auto combined = withOpacityMap(*colour, *opacityBytes, why)) {
                pbr.baseColorTexture.index = w.madeTexture(std::move(*combined), (base >= 0 ? colourLabel + " with alpha from " : "alpha from ") + opacityLabel);
                if (g.alphaMode == "OPAQUE") g.alphaMode = "BLEND";
            } else {
                notes.push_back(where + ": opacity map \"" + printable(opacityMap) + "\" not used (" + why + ")");
            }
        }
    } else if (!opacityMap.empty() && g.alphaMode == "OPAQUE") {
        g.alphaMode = "BLEND";
    }
    // Blender draws both sides; these formats have no notion of one.
    g.doubleSided = true;
    return g;
}

/// STL and PLY materials are assimp's own defaults: the neutral grey Blender gives a new
/// object, or white under vertex colours so that the colours are the colour.
tinygltf::Material neutral(bool vertexColours) {
    tinygltf::Material g;
    g.name = vertexColours ? "vertex colours" : "default";
    const double b = vertexColours ? 1.0 : 0.8;
    g.pbrMetallicRoughness.baseColorFactor = {b, b, b, 1.0};
    g.pbrMetallicRoughness.metallicFactor = 0.0;
    g.pbrMetallicRoughness.roughnessFactor = 0.5;
    g.doubleSided = true;
    return g;
}

std::string firstLine(const std::string& s) {
    const size_t b = s.find_first_not_of(" \n\r\t");
    if (b == std::string::npos) return "";
    const size_t e = s.find_first_of("\r\n", b);
    return s.substr(b, e == std::string::npos ? std::string::npos : e - b);
}

/// Counts a file declares that no file of its size can hold, before assimp reserves room for
/// them (its COLLADA reader reserves a float_array's count="N" as it is, so a 300-byte file
/// asked for 3 GB under the fuzzer): COLLADA's count="N" attributes and a PLY header's
/// "element NAME N". Each counted item takes at least one byte of the file, so N above the
/// file's size is refused. Returns why, or "".
std::string impossibleCount(const std::string& ext, const std::string& bytes) {
    auto number = [&](size_t at, size_t& end) {
        uint64_t v = 0;
        end = at;
        while (end < bytes.size() && bytes[end] >= '0' && bytes[end] <= '9' && end - at < 19) v = v * 10 + uint64_t(bytes[end++] - '0');
        return end > at ? v : 0;
    };
    if (ext == ".dae") {
        for (size_t at = bytes.find("count="); at != std::string::npos; at = bytes.find("count=", at + 6)) {
            size_t q = at + 6, end = 0;
            if (q >= bytes.size() || (bytes[q] != '"' && bytes[q] != '\'')) continue;
            const uint64_t n = number(q + 1, end);
            if (n > bytes.size())
                return "declares count=\"" + std::to_string(n) + "\", more than its " + std::to_string(bytes.size()) + " bytes can hold";
        }
    } else if (ext == ".ply") {
        const size_t header = std::min(bytes.find("end_header"), bytes.size());
        for (size_t at = bytes.find("element "); at < header; at = bytes.find("element ", at + 8)) {
            size_t nameEnd = bytes.find(' ', at + 8), end = 0;
            if (nameEnd == std::string::npos || nameEnd >= header) break;
            const uint64_t n = number(nameEnd + 1, end);
            if (n > bytes.size())
                return "header declares " + std::to_string(n) + " " + bytes.substr(at + 8, std::min<size_t>(nameEnd - at - 8, 32)) +
                       " elements, more than its " + std::to_string(bytes.size()) + " bytes can hold";
        }
    }
    return "";
}

}  // namespace

std::string assimpFormatList() { return ".obj, .stl, .ply, .fbx, .dae and .3mf"; }

std::string unvouchedAssimpFormat(const std::string& path) {
    const std::string e = lowerExtension(path);
    if (e.size() < 2 || isAssimpPath(path) || isGltfPath(path) || e == ".json") return "";
    Assimp::Importer probe;
    if (!probe.IsExtensionSupported(e)) return "";
    return "rayfarm does not read " + e + " files (assimp could, but rayfarm is not tested on them); it reads .json scene files, "
           "glTF (.gltf, .glb) and through assimp " + assimpFormatList();
}

tinygltf::Model importAssimpModel(const std::string& path, FileSource& fs, const AssetOptions& assets, std::vector<std::string>& notes) {
    const std::string ext = lowerExtension(path);
    const char* formatName = "model";
    for (const Format& f : kFormats)
        if (ext == f.ext) formatName = f.name;
    LoadStep reading("reading the model through assimp");
    // The file first, against its size limit, so a message about it names it plainly.
    const uint64_t fileBytes = fs.read(path, Limits::kMaxFileBytes).size();
    if (const std::string why = impossibleCount(ext, fs.read(path, Limits::kMaxFileBytes)); !why.empty()) throw InputError(path, why);
    const std::string folderPath = std::filesystem::path(path).parent_path().string();
    const std::string folder = folderPath.empty() ? "." : folderPath;
    ConfinedFs confined(fs, folder, gltf::assetRootFor(path, assets.root));
    // assimp reads and post-processes the file in a child process (assimp_isolated.h).
    auto readFile = [&](ChildImportReport& report) -> const aiScene* {
        // Kept to the child's end (never deleted): it owns the scene returned, dumped after this.
        Assimp::Importer& importer = *new Assimp::Importer;
        auto* io = new ConfinedIoSystem(fs, path, confined);
        importer.SetIOHandler(io);  // the importer owns it
        importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, false);
        // Points and lines are kept (a PLY point cloud is drawn as dots), sorted from triangles.
        importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, 0);
        // Read first, then post-process: a point cloud (a PLY or OBJ of vertices alone) has no faces,
        // which assimp's validation refuses, so each of its vertices becomes a point first. The
        // validation then runs before any other step, as it does within ReadFile.
        const aiScene* scene = importer.ReadFile(path, 0);
        if (scene && scene->mMeshes) {
            for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
                aiMesh* m = scene->mMeshes[i];
                if (!m || m->mNumFaces != 0 || m->mFaces || m->mNumVertices == 0 || !m->mVertices) continue;
                m->mFaces = new aiFace[m->mNumVertices];  // freed by assimp's aiMesh (delete[])
                m->mNumFaces = m->mNumVertices;
                for (unsigned v = 0; v < m->mNumVertices; ++v) {
                    m->mFaces[v].mNumIndices = 1;
                    m->mFaces[v].mIndices = new unsigned[1]{v};
                }
                m->mPrimitiveTypes = aiPrimitiveType_POINT;
            }
        }
        const unsigned flags = aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_FlipUVs;
        if (scene) scene = importer.ApplyPostProcessing(flags);
        report.importerError = firstLine(importer.GetErrorString());
        report.violation = confined.violation();
        report.violationReason = confined.violationReason();
        report.ioError = io->error();
        report.filesRead = io->filesRead();
        return scene;
    };
    Assimp::Importer importer;
    ChildImportReport report;
    const aiScene* scene = importInChild(importer, path, fileBytes, readFile, report);
    // What the child read, read here too: the farm's bundle carries the side files.
    for (const auto& [file, limit] : report.filesRead) fs.read(file, limit);
    if (!report.violation.empty()) throw InputError(path, "file \"" + report.violation + "\": " + report.violationReason + "; refused");
    if (!report.ioError.empty()) throw InputError(path, "a file it names cannot be read: " + report.ioError);
    if (!scene) {
        const std::string& why = report.importerError;
        throw InputError(path, std::string("assimp cannot read it as ") + formatName + (why.empty() ? "" : ": " + why));
    }
    pollLoadCancel();
    LoadStep converting("turning it into the glTF model");
    std::vector<std::string> ownNotes;
    GltfWriter w(path, fs, confined, ownNotes);
    tinygltf::Model& g = w.model();
    g.asset.generator = std::string("assimp ") + std::to_string(aiGetVersionMajor()) + "." + std::to_string(aiGetVersionMinor()) + "." +
                        std::to_string(aiGetVersionPatch()) + " from " + formatName;
    size_t bytes = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i)
        if (const aiMesh* m = scene->mMeshes[i]) bytes += size_t(m->mNumVertices) * 48 + size_t(m->mNumFaces) * 12 + 64;
    w.reserve(bytes);

    // Materials: STL and PLY get the neutral ones (their formats have none); others as the file says.
    std::set<std::string> extensions;
    const bool neutralOnly = ext == ".stl" || ext == ".ply";
    int neutralPlain = -1, neutralColoured = -1;
    std::vector<int> materialOf(scene->mNumMaterials, -1);
    if (!neutralOnly)
        for (unsigned i = 0; i < scene->mNumMaterials; ++i)
            if (scene->mMaterials[i]) {
                g.materials.push_back(material(*scene, *scene->mMaterials[i], ext, w, ownNotes, extensions));
                materialOf[i] = int(g.materials.size() - 1);
            }
    auto neutralMaterial = [&](bool coloured) {
        int& slot = coloured ? neutralColoured : neutralPlain;
        if (slot < 0) {
            g.materials.push_back(neutral(coloured));
            slot = int(g.materials.size() - 1);
        }
        return slot;
    };

    std::vector<tinygltf::Primitive> prims(scene->mNumMeshes);
    std::vector<uint8_t> drawable(scene->mNumMeshes, 0);
    // Each mesh's bones as a glTF skin's data (assimp_skin.h); the skins themselves are made
    // once the nodes their joints name exist.
    std::vector<AssimpSkin> skins(scene->mNumMeshes);
    std::vector<AssimpMorph> morphs(scene->mNumMeshes);
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        pollLoadCancel();
        const aiMesh* m = scene->mMeshes[i];
        if (!m) continue;
        skins[i] = assimpSkin(*m);
        morphs[i] = assimpMorph(*m);
        if (morphs[i].unusable)
            ownNotes.push_back("mesh \"" + printable(m->mName.C_Str()) + "\": " + std::to_string(morphs[i].unusable) +
                               " morph target(s) without a position a vertex; left flat");
        if (!skins[i].refused.empty())
            ownNotes.push_back("mesh \"" + printable(m->mName.C_Str()) + "\" drawn in its bind pose: " + skins[i].refused);
        int mat = m->mMaterialIndex < materialOf.size() ? materialOf[m->mMaterialIndex] : -1;
        if (neutralOnly || mat < 0) mat = neutralMaterial(m->mColors[0] != nullptr);
        GltfWriter::Prim p = w.mesh(*m, mat, skins[i], morphs[i]);
        if (p.ok) prims[i] = std::move(p.prim), drawable[i] = 1;
    }

    // The node tree, iteratively (a file may nest deeply), under one root that turns the
    // format's axes and unit into glTF's.
    const AxisConversion axes = axisConversion(ext, *scene);
    if (!axes.note.empty()) ownNotes.push_back(axes.note);
    tinygltf::Node root;
    root.name = "rayfarm: axes and unit";
    if (axes.scale != 1.0 || axes.rows[1][1] != 1.0 || axes.rows[0][0] != 1.0 || axes.rows[2][2] != 1.0) {
        root.matrix.assign(16, 0.0);
        for (int r = 0; r < 3; ++r)
            for (int col = 0; col < 3; ++col) root.matrix[size_t(col * 4 + r)] = axes.rows[r][col] * axes.scale;
        root.matrix[15] = 1.0;
    }
    g.nodes.push_back(root);
    g.scenes.emplace_back();
    g.scenes[0].nodes = {0};
    g.defaultScene = 0;
    // Nodes an animation moves carry translation, rotation and scale (glTF animates those, not
    // a matrix); their channels are matched by name, as assimp matches them.
    std::set<std::string> animatedNames;
    for (unsigned a = 0; a < scene->mNumAnimations; ++a)
        if (const aiAnimation* an = scene->mAnimations[a])
            for (unsigned c = 0; c < an->mNumChannels; ++c)
                if (an->mChannels && an->mChannels[c]) animatedNames.insert(an->mChannels[c]->mNodeName.C_Str());
    std::map<std::string, int> nodeByName;
    std::vector<OwnNode> ownNodes;
    std::vector<std::pair<const aiNode*, int>> stack;  // (node, its parent's glTF index)
    if (scene->mRootNode) stack.emplace_back(scene->mRootNode, 0);
    size_t visited = 0;
    const size_t maxNodes = size_t(1) << 22;
    while (!stack.empty()) {
        const auto [n, parent] = stack.back();
        stack.pop_back();
        if (++visited > maxNodes) throw InputError(path, "more than " + std::to_string(maxNodes) + " nodes; refused");
        tinygltf::Node node;
        node.name = n->mName.C_Str();
        const aiMatrix4x4& t = n->mTransformation;
        if (animatedNames.count(node.name)) {
            aiVector3D scaling, position;
            aiQuaternion rotation;
            t.Decompose(scaling, rotation, position);
            node.translation = {position.x, position.y, position.z};
            node.rotation = {rotation.x, rotation.y, rotation.z, rotation.w};
            node.scale = {scaling.x, scaling.y, scaling.z};
        } else if (!t.IsIdentity()) {
            const float rows[4][4] = {{t.a1, t.a2, t.a3, t.a4}, {t.b1, t.b2, t.b3, t.b4}, {t.c1, t.c2, t.c3, t.c4}, {t.d1, t.d2, t.d3, t.d4}};
            node.matrix.resize(16);
            for (int r = 0; r < 4; ++r)
                for (int col = 0; col < 4; ++col) node.matrix[size_t(col * 4 + r)] = rows[r][col];
        }
        tinygltf::Mesh mesh;
        mesh.name = node.name;
        std::vector<unsigned> own;
        for (unsigned k = 0; k < n->mNumMeshes; ++k) {
            const unsigned mi = n->mMeshes ? n->mMeshes[k] : scene->mNumMeshes;
            if (mi >= scene->mNumMeshes || !drawable[mi]) continue;
            if (skins[mi].sets > 0 || morphs[mi].targets() > 0) own.push_back(mi);
            else mesh.primitives.push_back(prims[mi]);
        }
        if (!mesh.primitives.empty()) {
            g.meshes.push_back(std::move(mesh));
            node.mesh = int(g.meshes.size() - 1);
        }
        const int index = int(g.nodes.size());
        nodeByName.emplace(node.name, index);
        g.nodes.push_back(std::move(node));
        g.nodes[size_t(parent)].children.push_back(index);
        // A glTF node has one skin and one set of morph weights, but each of assimp's meshes
        // has bones and targets of its own: each such mesh is drawn by a node of its own under
        // the one that holds it (whose transform a skin then ignores).
        for (const unsigned mi : own) {
            tinygltf::Node drawer;
            drawer.name = g.nodes[size_t(index)].name + " (mesh " + std::to_string(mi) + ")";
            tinygltf::Mesh one;
            one.name = scene->mMeshes[mi]->mName.C_Str();
            one.primitives = {prims[mi]};
            one.weights.assign(morphs[mi].targets(), 0.0);
            g.meshes.push_back(std::move(one));
            drawer.mesh = int(g.meshes.size() - 1);
            const int at = int(g.nodes.size());
            g.nodes.push_back(std::move(drawer));
            g.nodes[size_t(index)].children.push_back(at);
            ownNodes.push_back({at, mi, index});
        }
        for (unsigned k = n->mNumChildren; k-- > 0;)
            if (n->mChildren && n->mChildren[k]) stack.emplace_back(n->mChildren[k], index);
    }
    g.extensionsUsed.assign(extensions.begin(), extensions.end());
    makeSkins(g, *scene, skins, ownNodes, nodeByName, ownNotes, [&](const std::vector<float>& m) {
        return w.accessor(w.view(m.data(), m.size() * sizeof(float), 0), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, m.size() / 16);
    });

    // Node animations: each channel's position, rotation and scale keys as glTF samplers (LINEAR;
    // times from assimp's ticks at its ticks per second, 25 when the file names none). Keys
    // whose time does not increase are left out, as glTF requires increasing times.
    size_t animationsRead = 0, morphChannelsUnplaced = 0, morphKeysOutOfRange = 0;
    for (unsigned a = 0; a < scene->mNumAnimations; ++a) {
        const aiAnimation* an = scene->mAnimations[a];
        if (!an) continue;
        const double tps = an->mTicksPerSecond > 0.0 && std::isfinite(an->mTicksPerSecond) ? an->mTicksPerSecond : 25.0;
        tinygltf::Animation ga;
        ga.name = an->mName.C_Str();
        auto sampler = [&](int node, const char* target, size_t count, auto time, auto value, int type, int width) {
            std::vector<float> in, out;
            double last = -1.0;
            for (size_t k = 0; k < count; ++k) {
                const double t = time(k) / tps;
                if (!(t > last) || !std::isfinite(t)) continue;
                last = t;
                in.push_back(float(t));
                value(k, out);
            }
            if (in.empty() || out.size() != in.size() * size_t(width)) return;
            tinygltf::AnimationSampler smp;
            smp.input = w.accessor(w.view(in.data(), in.size() * 4, 0), TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, in.size(),
                                   {double(in.front())}, {double(in.back())});
            // As many elements as keys, but for weights: a scalar a target a key.
            smp.output = w.accessor(w.view(out.data(), out.size() * 4, 0), TINYGLTF_COMPONENT_TYPE_FLOAT, type,
                                    out.size() / size_t(tinygltf::GetNumComponentsInType(uint32_t(type))));
            smp.interpolation = "LINEAR";
            ga.samplers.push_back(smp);
            tinygltf::AnimationChannel ch;
            ch.sampler = int(ga.samplers.size() - 1);
            ch.target_node = node;
            ch.target_path = target;
            ga.channels.push_back(ch);
        };
        for (unsigned c = 0; c < an->mNumChannels && an->mChannels; ++c) {
            const aiNodeAnim* ch = an->mChannels[c];
            if (!ch) continue;
            const auto it = nodeByName.find(ch->mNodeName.C_Str());
            if (it == nodeByName.end()) continue;
            if (ch->mPositionKeys && ch->mNumPositionKeys)
                sampler(it->second, "translation", ch->mNumPositionKeys, [&](size_t k) { return ch->mPositionKeys[k].mTime; },
                        [&](size_t k, std::vector<float>& o) { const aiVector3D& v = ch->mPositionKeys[k].mValue; o.insert(o.end(), {v.x, v.y, v.z}); },
                        TINYGLTF_TYPE_VEC3, 3);
            if (ch->mRotationKeys && ch->mNumRotationKeys)
                sampler(it->second, "rotation", ch->mNumRotationKeys, [&](size_t k) { return ch->mRotationKeys[k].mTime; },
                        [&](size_t k, std::vector<float>& o) {
                            aiQuaternion q = ch->mRotationKeys[k].mValue;
                            q.Normalize();
                            o.insert(o.end(), {q.x, q.y, q.z, q.w});
                        },
                        TINYGLTF_TYPE_VEC4, 4);
            if (ch->mScalingKeys && ch->mNumScalingKeys)
                sampler(it->second, "scale", ch->mNumScalingKeys, [&](size_t k) { return ch->mScalingKeys[k].mTime; },
                        [&](size_t k, std::vector<float>& o) { const aiVector3D& v = ch->mScalingKeys[k].mValue; o.insert(o.end(), {v.x, v.y, v.z}); },
                        TINYGLTF_TYPE_VEC3, 3);
        }
        // Morph channels: each the "weights" of the nodes of the node it names that draw a mesh
        // with targets, resampled to one row of weights a key (glTF's layout).
        for (unsigned c = 0; c < an->mNumMorphMeshChannels && an->mMorphMeshChannels; ++c) {
            const aiMeshMorphAnim* ch = an->mMorphMeshChannels[c];
            if (!ch) continue;
            const std::string target = morphChannelNode(ch->mName.C_Str());
            bool placed = false;
            for (const OwnNode& on : ownNodes) {
                const size_t targets = morphs[on.mesh].targets();
                if (targets == 0 || g.nodes[size_t(on.holder)].name != target) continue;
                const MorphTrack track = morphTrack(*ch, targets);
                morphKeysOutOfRange += track.outOfRange;
                sampler(on.node, "weights", track.times.size(), [&](size_t k) { return track.times[k]; },
                        [&](size_t k, std::vector<float>& o) {
                            o.insert(o.end(), track.weights.begin() + std::ptrdiff_t(k * targets),
                                     track.weights.begin() + std::ptrdiff_t((k + 1) * targets));
                        },
                        TINYGLTF_TYPE_SCALAR, int(targets));
                placed = true;
            }
            if (!placed) ++morphChannelsUnplaced;
        }
        if (!ga.channels.empty()) {
            g.animations.push_back(std::move(ga));
            ++animationsRead;
        }
    }

    if (morphChannelsUnplaced)
        ownNotes.push_back(std::to_string(morphChannelsUnplaced) + " morph animation channel(s) naming no node with morph targets not played");
    if (morphKeysOutOfRange) ownNotes.push_back(std::to_string(morphKeysOutOfRange) + " morph keys naming a target the mesh lacks ignored");
    if (scene->mNumAnimations > animationsRead)
        ownNotes.push_back(std::to_string(scene->mNumAnimations - animationsRead) + " animation(s) without a channel on a node not played");
    if (scene->mNumCameras) ownNotes.push_back(std::to_string(scene->mNumCameras) + " camera(s) in the file not used");
    if (scene->mNumLights)
        ownNotes.push_back(std::to_string(scene->mNumLights) + " light(s) in the file not used; the model is lit as a glTF without lights");
    notes.insert(notes.end(), ownNotes.begin(), ownNotes.end());
    return w.take();
}

void loadAssimpModel(Scene& scene, const std::string& path, const DMat4& worldFromModel, FileSource& fs, int materialOverride,
                     const AssetOptions& assets) {
    std::vector<std::string> notes;
    tinygltf::Model model = importAssimpModel(path, fs, assets, notes);
    loadGltfModel(scene, path, std::move(model), std::move(notes), worldFromModel, materialOverride, assets);
}

namespace {

GltfInfo describe(const std::string& path, const tinygltf::Model& model, const AssetOptions& assets) {
    GltfInfo info = inspectGltf(path, model, assets);
    const std::string ext = lowerExtension(path);
    for (const Format& f : kFormats)
        if (ext == f.ext) info.format = f.name;
    return info;
}

}  // namespace

Scene loadAssimpScene(const std::string& path, FileSource& fs, const SceneOptions& options, GltfInfo* inspect) {
    std::vector<std::string> notes;
    tinygltf::Model model = importAssimpModel(path, fs, options.assets, notes);
    if (inspect) *inspect = describe(path, model, options.assets);
    return loadGltfScene(path, std::move(model), std::move(notes), fs, options);
}

GltfInfo inspectAssimp(const std::string& path, FileSource& fs, const AssetOptions& assets) {
    std::vector<std::string> notes;
    return describe(path, importAssimpModel(path, fs, assets, notes), assets);
}

}  // namespace rf
