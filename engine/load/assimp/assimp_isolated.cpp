#include "engine/load/assimp/assimp_isolated.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <new>
#include <stdexcept>

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/mesh.h>
#include <assimp/scene.h>

#include "engine/util/errors.h"
#include "engine/util/load_control.h"

// Sanitizer runtimes (ASan, UBSan, libFuzzer's) call their death callback on a report; in the
// child that callback belongs to the parent (libFuzzer would write the parent's input as a
// crash of its own). Weak: absent from a plain build.
extern "C" __attribute__((weak)) void __sanitizer_set_death_callback(void (*)(void));

namespace rf {

namespace {

/// The scene's metadata (FBX's axes and unit) rides on a wrapper root node: assimp's binary dump
/// keeps nodes' metadata but not the scene's.
constexpr const char* kMetadataNode = "$rayfarm-scene-metadata$";
constexpr char kMagic[4] = {'R', 'F', 'A', 'I'};

void putU64(std::string& out, uint64_t v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }
void putString(std::string& out, const std::string& s) {
    putU64(out, s.size());
    out += s;
}

/// Reads the child's message; throws std::runtime_error where it is short or malformed.
class Reader {
public:
    explicit Reader(const std::string& bytes) : bytes_(bytes) {}
    uint64_t u64() {
        need(8);
        uint64_t v;
        std::memcpy(&v, bytes_.data() + pos_, 8);
        pos_ += 8;
        return v;
    }
    std::string string() {
        const uint64_t n = u64();
        need(n);
        std::string s = bytes_.substr(pos_, n);
        pos_ += n;
        return s;
    }
    const char* take(uint64_t n) {
        need(n);
        const char* p = bytes_.data() + pos_;
        pos_ += n;
        return p;
    }
    /// count elements of size bytes, the product checked without overflow.
    const char* takeArray(uint64_t count, uint64_t size) {
        if (size != 0 && count > remaining() / size) throw std::runtime_error("truncated");
        return take(count * size);
    }
    uint64_t remaining() const { return bytes_.size() - pos_; }
    /// A count of records of at least minBytes each that the bytes left can hold: checked before
    /// anything is allocated for them.
    unsigned records(uint64_t minBytes) {
        const uint64_t n = u64();
        if (n > UINT32_MAX || n > remaining() / minBytes) throw std::runtime_error("count beyond the message");
        return unsigned(n);
    }
    bool atEnd() const { return pos_ == bytes_.size(); }

private:
    void need(uint64_t n) const {
        if (n > bytes_.size() - pos_) throw std::runtime_error("truncated");
    }
    const std::string& bytes_;
    size_t pos_ = 0;
};

bool writeAll(int fd, const char* p, size_t n) {
    while (n > 0) {
        const ssize_t w = ::write(fd, p, std::min<size_t>(n, 1 << 20));
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= size_t(w);
    }
    return true;
}

/// The process's data now (bytes): its private writable mappings, /proc's VmData, which is what
/// RLIMIT_DATA bounds (Linux 4.7 on). Under AddressSanitizer that includes the shadow it reserved
/// at start, so the same limit works there.
uint64_t currentData() {
    std::ifstream status("/proc/self/status");
    std::string key;
    uint64_t kib = 0;
    while (status >> key) {
        if (key == "VmData:") {
            status >> kib;
            return kib << 10;
        }
        status.ignore(1 << 12, '\n');
    }
    return 0;
}

/// A mesh's per-vertex arrays and faces travel raw beside the dump: assimp's binary writer and
/// reader handle them value by value (1.5 s for a 10⁶-triangle STL), a copy of the bytes does not.
/// In the child they are taken out of the mesh before the dump (left to the child's end) and
/// listed as byte ranges to write; the parent puts them back into the mesh it read.
struct Segment {
    const void* data;
    size_t bytes;
};
constexpr unsigned kColorSets = AI_MAX_NUMBER_OF_COLOR_SETS, kUvSets = AI_MAX_NUMBER_OF_TEXTURECOORDS;

/// The arrays of a mesh or a morph target (aiAnimMesh), in a fixed order: positions, normals,
/// tangents, bitangents, colours, UVs.
template <class Mesh>
std::vector<std::pair<void**, size_t>> vertexArrays(Mesh& m) {
    std::vector<std::pair<void**, size_t>> a;
    const auto vec = sizeof(aiVector3D), col = sizeof(aiColor4D);
    a.emplace_back(reinterpret_cast<void**>(&m.mVertices), vec);
    a.emplace_back(reinterpret_cast<void**>(&m.mNormals), vec);
    a.emplace_back(reinterpret_cast<void**>(&m.mTangents), vec);
    a.emplace_back(reinterpret_cast<void**>(&m.mBitangents), vec);
    for (unsigned c = 0; c < kColorSets; ++c) a.emplace_back(reinterpret_cast<void**>(&m.mColors[c]), col);
    for (unsigned t = 0; t < kUvSets; ++t) a.emplace_back(reinterpret_cast<void**>(&m.mTextureCoords[t]), vec);
    return a;
}

/// Child: the header of every mesh into msg, their arrays into segments (faces flattened into
/// faceData, which must outlive the writes), and the meshes emptied for the dump.
void takeMeshArrays(aiScene& scene, std::string& msg, std::vector<Segment>& segments, std::vector<std::vector<uint32_t>>& faceData) {
    putU64(msg, scene.mNumMeshes);
    faceData.reserve(scene.mNumMeshes);
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        aiMesh& m = *scene.mMeshes[i];
        uint64_t present = 0;
        const auto arrays = vertexArrays(m);
        for (size_t k = 0; k < arrays.size(); ++k)
            if (*arrays[k].first) present |= uint64_t(1) << k;
        putU64(msg, m.mNumVertices);
        putU64(msg, present);
        for (unsigned t = 0; t < kUvSets; ++t) putU64(msg, m.mNumUVComponents[t]);
        std::vector<uint32_t>& faces = faceData.emplace_back();  // counts, then the indices
        size_t indices = 0;
        for (unsigned f = 0; f < m.mNumFaces; ++f) indices += m.mFaces[f].mNumIndices;
        faces.reserve(m.mNumFaces + indices);
        for (unsigned f = 0; f < m.mNumFaces; ++f) faces.push_back(m.mFaces[f].mNumIndices);
        for (unsigned f = 0; f < m.mNumFaces; ++f) faces.insert(faces.end(), m.mFaces[f].mIndices, m.mFaces[f].mIndices + m.mFaces[f].mNumIndices);
        putU64(msg, m.mNumFaces);
        putU64(msg, indices);
        for (size_t k = 0; k < arrays.size(); ++k)
            if (*arrays[k].first) {
                segments.push_back({*arrays[k].first, arrays[k].second * m.mNumVertices});
                *arrays[k].first = nullptr;
            }
        segments.push_back({faces.data(), faces.size() * sizeof(uint32_t)});
        m.mNumVertices = 0;
        m.mNumFaces = 0;
        m.mFaces = nullptr;
        for (unsigned t = 0; t < kUvSets; ++t) m.mNumUVComponents[t] = 0;
    }
}

void putF64(std::string& out, double v) { out.append(reinterpret_cast<const char*>(&v), sizeof v); }

/// Child: what assimp's binary dump leaves out, into out: meshes' names, embedded textures' file
/// names (by which materials find them), morph targets (aiMesh::mAnimMeshes, mMethod) and morph
/// channels (aiAnimation::mMorphMeshChannels); the last two taken off the scene before the dump.
/// AssimpIsolated.EveryModelConvertsAsInProcess finds what else would be missing.
void takeExtras(aiScene& scene, std::string& out) {
    putU64(out, scene.mNumTextures);
    for (unsigned i = 0; i < scene.mNumTextures; ++i) putString(out, scene.mTextures[i] ? scene.mTextures[i]->mFilename.C_Str() : "");
    putU64(out, scene.mNumMeshes);
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        aiMesh& m = *scene.mMeshes[i];
        putString(out, m.mName.C_Str());
        const unsigned n = m.mAnimMeshes ? m.mNumAnimMeshes : 0;
        putU64(out, n);
        putU64(out, m.mMethod);
        for (unsigned t = 0; t < n; ++t) {
            aiAnimMesh& a = *m.mAnimMeshes[t];
            putString(out, a.mName.C_Str());
            putU64(out, a.mNumVertices);
            putF64(out, a.mWeight);
            const auto arrays = vertexArrays(a);
            uint64_t present = 0;
            for (size_t k = 0; k < arrays.size(); ++k)
                if (*arrays[k].first) present |= uint64_t(1) << k;
            putU64(out, present);
            for (const auto& [array, size] : arrays)
                if (*array) out.append(static_cast<const char*>(*array), size * a.mNumVertices);
        }
        m.mNumAnimMeshes = 0;
        m.mAnimMeshes = nullptr;
    }
    putU64(out, scene.mNumAnimations);
    for (unsigned i = 0; i < scene.mNumAnimations; ++i) {
        aiAnimation& an = *scene.mAnimations[i];
        const unsigned n = an.mMorphMeshChannels ? an.mNumMorphMeshChannels : 0;
        putU64(out, n);
        for (unsigned c = 0; c < n; ++c) {
            const aiMeshMorphAnim& ch = *an.mMorphMeshChannels[c];
            putString(out, ch.mName.C_Str());
            const unsigned keys = ch.mKeys ? ch.mNumKeys : 0;
            putU64(out, keys);
            for (unsigned k = 0; k < keys; ++k) {
                const aiMeshMorphKey& key = ch.mKeys[k];
                const unsigned values = key.mValues && key.mWeights ? key.mNumValuesAndWeights : 0;
                putF64(out, key.mTime);
                putU64(out, values);
                out.append(reinterpret_cast<const char*>(key.mValues), values * sizeof(unsigned));
                out.append(reinterpret_cast<const char*>(key.mWeights), values * sizeof(double));
            }
        }
        an.mNumMorphMeshChannels = 0;
        an.mMorphMeshChannels = nullptr;
    }
}

/// The child: reads, dumps the scene and writes the message; never returns.
[[noreturn]] void runChild(int fd, pid_t parent, uint64_t memoryBytes, const std::function<const aiScene*(ChildImportReport&)>& read) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(3);
    if (__sanitizer_set_death_callback) __sanitizer_set_death_callback(nullptr);
    // The pipe above the standard descriptors (a parent started without them got it there), so
    // that quieting them below does not close it.
    if (fd <= STDERR_FILENO) fd = ::fcntl(fd, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
    // Quiet: a crash's message (glibc's "double free detected", a sanitizer's report) would be a
    // second line beside rayfarm's one. glibc writes those to the controlling terminal, which
    // a session of its own does not have; the standard descriptors go nowhere.
    ::setsid();
    if (const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC); null >= 0) {
        for (int to : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) ::dup2(null, to);
    }
    // A crash ends the child plainly (the parent names the signal), not through handlers the
    // parent installed (the farm's interrupt handlers, a fuzzer's crash handlers) nor a mask the
    // forking thread had; and without a core dump (a crash is the case this is for, and a core
    // would hold a copy of the parent's scene).
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGSEGV, SIGBUS, SIGABRT, SIGILL, SIGFPE, SIGPIPE}) std::signal(sig, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const rlimit noCore{0, 0};
    ::setrlimit(RLIMIT_CORE, &noCore);
    ::prctl(PR_SET_DUMPABLE, 0);
    if (const uint64_t now = currentData(); now > 0) {
        const rlimit limit{now + memoryBytes, RLIM_INFINITY};
        ::setrlimit(RLIMIT_DATA, &limit);
    }
    std::string msg(kMagic, sizeof kMagic);
    std::string failure;
    ChildImportReport report;
    const aiExportDataBlob* blob = nullptr;
    Assimp::Exporter exporter;
    std::string meshHeaders, extras;
    std::vector<Segment> segments;
    std::vector<std::vector<uint32_t>> faceData;
    try {
        const aiScene* constScene = read(report);
        if (constScene) {
            auto* scene = const_cast<aiScene*>(constScene);  // the child's own importer's; it ends here
            if (scene->mRootNode) {
                auto* wrapper = new aiNode(kMetadataNode);
                wrapper->mMetaData = scene->mMetaData;
                scene->mMetaData = nullptr;
                wrapper->mNumChildren = 1;
                wrapper->mChildren = new aiNode*[1]{scene->mRootNode};
                scene->mRootNode->mParent = wrapper;
                scene->mRootNode = wrapper;
            }
            takeMeshArrays(*scene, meshHeaders, segments, faceData);
            takeExtras(*scene, extras);
            blob = exporter.ExportToBlob(scene, "assbin");
            if (!blob) failure = std::string("assimp could not pass the scene on: ") + exporter.GetErrorString();
        }
    } catch (const std::bad_alloc&) {
        failure = "out of memory";
    } catch (const std::exception& e) {
        failure = e.what();
    } catch (...) {
        failure = "an unknown exception";
    }
    msg += char(blob ? 1 : 0);
    for (const std::string* s : {&report.importerError, &report.violation, &report.violationReason, &report.ioError, &failure})
        putString(msg, *s);
    putU64(msg, report.filesRead.size());
    for (const auto& [file, limit] : report.filesRead) {
        putString(msg, file);
        putU64(msg, limit);
    }
    putU64(msg, blob ? blob->size : 0);
    // The length of all that follows the magic and this length, so the parent can reserve it.
    uint64_t total = msg.size() - sizeof kMagic;
    if (blob) {
        total += blob->size + meshHeaders.size() + extras.size();
        for (const Segment& g : segments) total += g.bytes;
    }
    msg.insert(sizeof kMagic, reinterpret_cast<const char*>(&total), sizeof total);
    bool ok = writeAll(fd, msg.data(), msg.size());
    if (ok && blob) ok = writeAll(fd, static_cast<const char*>(blob->data), blob->size);
    if (ok && blob) ok = writeAll(fd, meshHeaders.data(), meshHeaders.size());
    for (const Segment& g : segments)
        if (ok && blob) ok = writeAll(fd, static_cast<const char*>(g.data), g.bytes);
    if (ok && blob) ok = writeAll(fd, extras.data(), extras.size());
    ::close(fd);
    ::_exit(ok ? 0 : 4);  // no atexit handlers, no stdio flush: the parent's, not the child's
}

std::string signalName(int sig) {
    const char* d = ::strsignal(sig);
    return "signal " + std::to_string(sig) + (d ? std::string(", ") + d : std::string());
}

/// The parent's hold on the child: on every way out (an exception included) its pipe is closed
/// and the child killed and reaped, unless reap() already reaped it.
class ChildHold {
public:
    ChildHold(pid_t pid, int fd) : pid_(pid), fd_(fd) {}
    ChildHold(const ChildHold&) = delete;
    ChildHold& operator=(const ChildHold&) = delete;
    ~ChildHold() { end(); }
    void closePipe() {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }
    /// Kills and reaps the child (it may be gone already).
    void end() {
        closePipe();
        if (pid_ <= 0) return;
        ::kill(pid_, SIGKILL);
        while (::waitpid(pid_, nullptr, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
    }
    /// The child's exit status once it ends, which it does right after its message; killed if it
    /// has not within a few seconds (0 where no status can be had).
    int reap() {
        closePipe();
        if (pid_ <= 0) return 0;
        const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        int status = 0;
        for (;;) {
            const pid_t w = ::waitpid(pid_, &status, WNOHANG);
            if (w == pid_) break;
            if (w < 0 && errno != EINTR) {
                status = 0;
                break;
            }
            if (std::chrono::steady_clock::now() > giveUp) {
                ::kill(pid_, SIGKILL);
                while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
                }
                break;
            }
            ::usleep(2000);
        }
        pid_ = -1;
        return status;
    }

private:
    pid_t pid_;
    int fd_;
};

/// Frees an array the dump's reader may have left in a slot the raw arrays replace (typed as
/// assimp's destructors free it).
void freeArray(void* p, size_t elementSize) {
    if (elementSize == sizeof(aiColor4D)) delete[] static_cast<aiColor4D*>(p);
    else delete[] static_cast<aiVector3D*>(p);
}

/// Parent: the vertex arrays present names (a bit each, vertexArrays' order), count elements
/// each, into a mesh or a morph target, allocated as assimp's destructors free them.
template <class Mesh>
void putVertexArrays(Mesh& m, uint64_t present, uint64_t count, Reader& in) {
    const auto arrays = vertexArrays(m);
    for (size_t k = 0; k < arrays.size(); ++k) {
        if (!(present >> k & 1)) continue;
        const char* src = in.takeArray(count, arrays[k].second);
        void* dst = arrays[k].second == sizeof(aiColor4D) ? static_cast<void*>(new aiColor4D[count])
                                                          : static_cast<void*>(new aiVector3D[count]);
        std::memcpy(dst, src, arrays[k].second * count);
        freeArray(*arrays[k].first, arrays[k].second);
        *arrays[k].first = dst;
    }
}

/// Parent: the arrays takeMeshArrays sent, back into the meshes read from the dump.
void putMeshArrays(aiScene& scene, Reader& in) {
    if (in.u64() != scene.mNumMeshes) throw std::runtime_error("mesh count");
    struct Header {
        uint64_t vertices, present, uv[kUvSets], faces, indices;
    };
    std::vector<Header> headers(scene.mNumMeshes);
    for (Header& h : headers) {
        h.vertices = in.u64();
        h.present = in.u64();
        for (uint64_t& c : h.uv) c = in.u64();
        h.faces = in.u64();
        h.indices = in.u64();
        if (h.vertices > UINT32_MAX || h.faces > UINT32_MAX || h.present >> (4 + kColorSets + kUvSets)) throw std::runtime_error("mesh header");
    }
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        aiMesh& m = *scene.mMeshes[i];
        const Header& h = headers[i];
        putVertexArrays(m, h.present, h.vertices, in);
        m.mNumVertices = unsigned(h.vertices);
        for (unsigned t = 0; t < kUvSets; ++t) m.mNumUVComponents[t] = unsigned(h.uv[t]);
        const char* counts = in.takeArray(h.faces, sizeof(uint32_t));  // unaligned in the message: copied out
        const char* indices = in.takeArray(h.indices, sizeof(uint32_t));
        delete[] m.mFaces;  // the reader's empty array (new aiFace[0] still allocates)
        m.mFaces = new aiFace[h.faces];
        m.mNumFaces = unsigned(h.faces);
        uint64_t at = 0;
        for (uint64_t f = 0; f < h.faces; ++f) {
            uint32_t n;
            std::memcpy(&n, counts + f * sizeof n, sizeof n);
            if (n > h.indices - at) throw std::runtime_error("face indices");
            m.mFaces[f].mNumIndices = n;
            m.mFaces[f].mIndices = new unsigned[n];
            std::memcpy(m.mFaces[f].mIndices, indices + at * sizeof(uint32_t), n * sizeof(uint32_t));
            at += n;
        }
        if (at != h.indices) throw std::runtime_error("face indices");
    }
}

/// Parent: what takeExtras sent, back onto the scene read from the dump.
void putExtras(aiScene& scene, Reader& in) {
    auto count = [&in](uint64_t limit) {
        const uint64_t n = in.u64();
        if (n > limit) throw std::runtime_error("morph count");
        return unsigned(n);
    };
    auto f64 = [&in] {
        double v;
        std::memcpy(&v, in.take(sizeof v), sizeof v);
        return v;
    };
    if (in.u64() != scene.mNumTextures) throw std::runtime_error("texture count");
    for (unsigned i = 0; i < scene.mNumTextures; ++i) {
        const std::string name = in.string();
        if (scene.mTextures[i]) scene.mTextures[i]->mFilename = aiString(name);
    }
    if (in.u64() != scene.mNumMeshes) throw std::runtime_error("mesh count");
    for (unsigned i = 0; i < scene.mNumMeshes; ++i) {
        aiMesh& m = *scene.mMeshes[i];
        m.mName = aiString(in.string());
        const unsigned n = in.records(32);  // an anim mesh: name, vertices, weight, arrays present
        m.mMethod = count(UINT32_MAX);
        if (n == 0) continue;
        delete[] m.mAnimMeshes;  // none were sent in the dump: an empty array at most
        m.mAnimMeshes = new aiAnimMesh*[n]();
        m.mNumAnimMeshes = n;
        for (unsigned t = 0; t < n; ++t) {
            aiAnimMesh& a = *(m.mAnimMeshes[t] = new aiAnimMesh());
            a.mName = aiString(in.string());
            a.mNumVertices = count(UINT32_MAX);
            a.mWeight = float(f64());
            const uint64_t present = in.u64();
            putVertexArrays(a, present, a.mNumVertices, in);
        }
    }
    if (in.u64() != scene.mNumAnimations) throw std::runtime_error("animation count");
    for (unsigned i = 0; i < scene.mNumAnimations; ++i) {
        aiAnimation& an = *scene.mAnimations[i];
        const unsigned n = in.records(16);  // a channel: name, keys
        if (n == 0) continue;
        delete[] an.mMorphMeshChannels;
        an.mMorphMeshChannels = new aiMeshMorphAnim*[n]();
        an.mNumMorphMeshChannels = n;
        for (unsigned c = 0; c < n; ++c) {
            aiMeshMorphAnim& ch = *(an.mMorphMeshChannels[c] = new aiMeshMorphAnim());
            ch.mName = aiString(in.string());
            const unsigned keys = in.records(16);  // a key: time, values
            ch.mKeys = new aiMeshMorphKey[keys];
            ch.mNumKeys = keys;
            for (unsigned k = 0; k < keys; ++k) {
                aiMeshMorphKey& key = ch.mKeys[k];
                key.mTime = f64();
                const unsigned values = count(UINT32_MAX);
                const char* v = in.takeArray(values, sizeof(unsigned));
                const char* w = in.takeArray(values, sizeof(double));
                if (values == 0) continue;
                auto valueArray = std::make_unique<unsigned[]>(values);
                auto weightArray = std::make_unique<double[]>(values);
                key.mValues = valueArray.release();
                key.mWeights = weightArray.release();
                key.mNumValuesAndWeights = values;
                std::memcpy(key.mValues, v, values * sizeof(unsigned));
                std::memcpy(key.mWeights, w, values * sizeof(double));
            }
        }
    }
}

/// Takes the wrapper root off again, putting its metadata back on the scene.
void unwrapMetadata(aiScene& scene) {
    aiNode* wrapper = scene.mRootNode;
    if (!wrapper || wrapper->mName != aiString(std::string(kMetadataNode)) || wrapper->mNumChildren != 1) return;
    aiNode* root = wrapper->mChildren[0];
    // assimp 5.2's ~aiNode frees the child array only with children in it: freed here.
    delete[] wrapper->mChildren;
    wrapper->mChildren = nullptr;
    wrapper->mNumChildren = 0;
    root->mParent = nullptr;
    delete scene.mMetaData;
    scene.mMetaData = wrapper->mMetaData;
    wrapper->mMetaData = nullptr;
    delete wrapper;
    scene.mRootNode = root;
}

/// The child's message into report and, where it made one, the scene in into. Throws
/// InputError: what the child says failed, or a malformed (short) message.
const aiScene* readMessage(Assimp::Importer& into, const std::string& path, const std::string& msg, ChildImportReport& report) {
    try {
        Reader in(msg);
        if (std::memcmp(in.take(sizeof kMagic), kMagic, sizeof kMagic) != 0) throw std::runtime_error("no header");
        if (in.u64() != msg.size() - sizeof kMagic - 8) throw std::runtime_error("short");
        const bool hasScene = *in.take(1) == 1;
        std::string failure;
        for (std::string* s : {&report.importerError, &report.violation, &report.violationReason, &report.ioError, &failure})
            *s = in.string();
        const uint64_t files = in.u64();
        for (uint64_t i = 0; i < files; ++i) {
            std::string file = in.string();
            report.filesRead.emplace_back(std::move(file), in.u64());
        }
        const uint64_t blobSize = in.u64();
        const char* blob = in.take(blobSize);
        if (!failure.empty()) throw InputError(path, "assimp failed on it: " + failure);
        if (!hasScene) {
            if (!in.atEnd()) throw std::runtime_error("trailing bytes");
            return nullptr;
        }
        const aiScene* scene = into.ReadFileFromMemory(blob, size_t(blobSize), 0, "assbin");
        if (!scene) throw InputError(path, std::string("could not read back the scene assimp made: ") + into.GetErrorString());
        auto& s = *const_cast<aiScene*>(scene);  // the importer's, which hands it to us to finish
        putMeshArrays(s, in);
        putExtras(s, in);
        if (!in.atEnd()) throw std::runtime_error("trailing bytes");
        unwrapMetadata(s);
        return scene;
    } catch (const std::runtime_error& e) {
        if (dynamic_cast<const InputError*>(&e)) throw;
        throw InputError(path, std::string("the importer's process sent a malformed answer (") + e.what() + ")");
    } catch (const std::bad_alloc&) {
        throw InputError(path, "out of memory reading back the scene assimp made");
    } catch (const std::length_error&) {
        throw InputError(path, "the importer's process sent a malformed answer (a size beyond any memory)");
    }
}

}  // namespace

const aiScene* readChildMessage(Assimp::Importer& into, const std::string& path, const std::string& msg, ChildImportReport& report) {
    return readMessage(into, path, msg, report);
}

const aiScene* importInChild(Assimp::Importer& into, const std::string& path, uint64_t inputBytes,
                             const std::function<const aiScene*(ChildImportReport&)>& read, ChildImportReport& report,
                             ChildImportLimits limits) {
    double seconds = limits.seconds > 0 ? limits.seconds : ChildImportLimits::kTimeBase + ChildImportLimits::kTimePerByte * double(inputBytes);
    // Tests and the fuzz harnesses shorten it (a fuzzer's own timeout is 25 s).
    if (const char* t = std::getenv("RAYFARM_TEST_ASSIMP_SECONDS"); t && limits.seconds <= 0 && std::atof(t) > 0) seconds = std::atof(t);
    const uint64_t memory = limits.memoryBytes > 0 ? limits.memoryBytes
                                                   : ChildImportLimits::kMemoryBase + ChildImportLimits::kMemoryPerByte * inputBytes;
    // Tests only: the same read in this process, to check that the child's answer carries all of
    // it (AssimpIsolated.EveryModelConvertsAsInProcess). The scene stays with read's importer.
    if (const char* e = std::getenv("RAYFARM_TEST_ASSIMP_IN_PROCESS"); e && *e == '1') return read(report);
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) throw InputError(path, std::string("cannot start the importer's process: ") + std::strerror(errno));
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw InputError(path, std::string("cannot start the importer's process: ") + std::strerror(e));
    }
    if (pid == 0) {
        ::close(fds[0]);
        runChild(fds[1], parent, memory, read);
    }
    ::close(fds[1]);
    ChildHold child(pid, fds[0]);
    ::fcntl(fds[0], F_SETPIPE_SZ, 1 << 20);  // fewer switches for a big scene; 64 KiB if refused

    // The message, read as it comes, while watching the clock and cancels, up to the length it
    // states (not only to the end of the pipe: another fork of this process may hold its end).
    std::string msg;
    uint64_t expected = 0;  // the whole message's length, once its header came
    const uint64_t maxMessage = memory + (64ull << 20);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    std::string stopped;  // why the parent stopped reading before the end
    std::vector<char> chunk(1 << 20);
    while (expected == 0 || msg.size() < expected) {
        if (loadCancelSignal() != 0) {
            child.end();
            pollLoadCancel();
        }
        if (std::chrono::steady_clock::now() > deadline) {
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.0f", seconds);
            stopped = std::string("assimp took longer than ") + buf + " s on it, the limit for a file of its size";
            break;
        }
        pollfd p{fds[0], POLLIN, 0};
        const int r = ::poll(&p, 1, 50);
        if (r < 0 && errno != EINTR) {
            stopped = std::string("lost the importer's process: ") + std::strerror(errno);
            break;
        }
        if (r <= 0) continue;
        const ssize_t n = ::read(fds[0], chunk.data(), chunk.size());
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) break;  // the end (or the child's death)
        if (msg.size() + size_t(n) > maxMessage) {
            stopped = "assimp made more of it than a file of its size may take";
            break;
        }
        msg.append(chunk.data(), size_t(n));
        if (expected == 0 && msg.size() >= sizeof kMagic + 8) {
            uint64_t total;
            std::memcpy(&total, msg.data() + sizeof kMagic, 8);
            if (total > maxMessage) {
                stopped = "assimp made more of it than a file of its size may take";
                break;
            }
            expected = sizeof kMagic + 8 + total;
            msg.reserve(expected);
        }
    }
    child.closePipe();
    if (!stopped.empty()) {
        child.end();
        throw InputError(path, stopped + "; refused");
    }
    // The message is read back before the child is reaped, so that its exit (unmapping all it
    // allocated) overlaps with the reading; its status then says why a message is short.
    auto whyDead = [](int status) -> std::string {
        if (WIFSIGNALED(status)) return "assimp crashed reading it (" + signalName(WTERMSIG(status)) + "); the file is refused";
        if (WIFEXITED(status) && WEXITSTATUS(status) != 0)
            return "assimp's process ended before it finished (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
        return "";
    };
    const aiScene* scene = nullptr;
    try {
        scene = readMessage(into, path, msg, report);
    } catch (const InputError&) {
        const std::string dead = whyDead(child.reap());
        pollLoadCancel();  // a cancel that came meanwhile wins
        if (!dead.empty()) throw InputError(path, dead);
        throw;
    }
    child.reap();
    return scene;
}

}  // namespace rf
