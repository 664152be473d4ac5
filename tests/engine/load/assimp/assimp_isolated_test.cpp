// assimp in a child process (assimp_isolated.h): a crash, a hang, a runaway allocation or a
// cancel in the importer costs the child, and the parent says which, with real processes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <sys/wait.h>
#include <unistd.h>

#include "engine/load/assimp/assimp_import.h"
#include "engine/load/assimp/assimp_isolated.h"
#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/util/load_control.h"

using namespace rf;

namespace {

/// The message importInChild throws for read, which must throw InputError.
std::string refusal(const std::function<const aiScene*(ChildImportReport&)>& read, ChildImportLimits limits = {}) {
    Assimp::Importer into;
    ChildImportReport report;
    try {
        importInChild(into, "model.fbx", 1000, read, report, limits);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no InputError";
    return "";
}

/// No child of this process is left (every one was reaped).
bool noChildLeft() { return ::waitpid(-1, nullptr, WNOHANG) < 0 && errno == ECHILD; }

}  // namespace

TEST(AssimpIsolated, ACrashInTheImporterIsRefusedNamingTheSignal) {
    const std::string why = refusal([](ChildImportReport&) -> const aiScene* { std::abort(); });
    EXPECT_EQ(why, "model.fbx: assimp crashed reading it (signal 6, Aborted); the file is refused");
    const std::string segv = refusal([](ChildImportReport&) -> const aiScene* {
        std::raise(SIGSEGV);
        return nullptr;
    });
    EXPECT_NE(segv.find("signal 11"), std::string::npos) << segv;
    EXPECT_TRUE(noChildLeft());
}

TEST(AssimpIsolated, AnImporterPastItsTimeIsKilled) {
    ChildImportLimits limits;
    limits.seconds = 0.5;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string why = refusal(
        [](ChildImportReport&) -> const aiScene* {
            for (;;) ::pause();
        },
        limits);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_NE(why.find("assimp took longer than"), std::string::npos) << why;
    EXPECT_GE(s, 0.5);
    EXPECT_LT(s, 20.0);  // the child loops forever: only the limit ends it (generous for a loaded machine)
    EXPECT_TRUE(noChildLeft());
}

TEST(AssimpIsolated, AnImporterOverItsMemoryIsRefused) {
    ChildImportLimits limits;
    limits.memoryBytes = 256ull << 20;
    const std::string why = refusal(
        [](ChildImportReport&) -> const aiScene* {
            // 2 GiB in one block, touched so that it would be real memory.
            auto* p = static_cast<volatile char*>(std::malloc(size_t(2) << 30));
            if (!p) throw std::bad_alloc();
            for (size_t i = 0; i < (size_t(2) << 30); i += 4096) p[i] = 1;
            return nullptr;
        },
        limits);
    // A plain build's malloc returns null (bad_alloc, caught in the child); AddressSanitizer's
    // allocator ends the child instead.
    EXPECT_TRUE(why.find("assimp failed on it: out of memory") != std::string::npos ||
                why.find("assimp's process ended before it finished") != std::string::npos)
        << why;
    EXPECT_TRUE(noChildLeft());
}

TEST(AssimpIsolated, ACancelKillsTheImporterAtOnce) {
    std::thread asker([] {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        requestLoadCancel(SIGINT);
    });
    const auto t0 = std::chrono::steady_clock::now();
    bool cancelled = false;
    try {
        Assimp::Importer into;
        ChildImportReport report;
        importInChild(into, "model.fbx", 1000, [](ChildImportReport&) -> const aiScene* {
            for (;;) ::pause();
        }, report);
    } catch (const LoadCancelled& c) {
        cancelled = c.signal == SIGINT;
    }
    asker.join();
    requestLoadCancel(0);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(cancelled);
    EXPECT_LT(s, 10.0);  // the child waits forever: only the cancel ends it
    EXPECT_TRUE(noChildLeft());
}

TEST(AssimpIsolated, WhatTheChildSaysReachesTheParent) {
    Assimp::Importer into;
    ChildImportReport report;
    const aiScene* scene = importInChild(into, "model.fbx", 1000, [](ChildImportReport& r) -> const aiScene* {
        r.importerError = "no meshes";
        r.violation = "../x.png";
        r.violationReason = "outside the asset root";
        r.filesRead = {{"model.fbx", 7}, {"side.mtl", 9}};
        return nullptr;
    }, report);
    EXPECT_EQ(scene, nullptr);
    EXPECT_EQ(report.importerError, "no meshes");
    EXPECT_EQ(report.violation, "../x.png");
    EXPECT_EQ(report.violationReason, "outside the asset root");
    ASSERT_EQ(report.filesRead.size(), 2u);
    EXPECT_EQ(report.filesRead[1].first, "side.mtl");
    EXPECT_EQ(report.filesRead[1].second, 9u);
}

// The file fuzzing found (Debian's libassimp 5.2 frees a buffer twice in its FBX importer):
// refused, and this process goes on. Whether glibc notices the double free depends on the heap's
// state (in one test binary it aborts, in another not), so the child either crashes or reads on
// and the texture the file names outside its folder is refused; either is one InputError.
TEST(AssimpIsolated, TheFbxThatCrashesAssimpIsRefused) {
    const std::string path = std::string(RAYFARM_SOURCE_DIR) + "/tests/fuzz/assimp_crashes/fbx-double-free.fbx";
    DiskFileSource fs;
    std::vector<std::string> notes;
    try {
        importAssimpModel(path, fs, {}, notes);
        FAIL() << "imported";
    } catch (const InputError& e) {
        const std::string why = e.what();
        // Under AddressSanitizer the child reports the double free and exits with status 1.
        EXPECT_TRUE(why.find("assimp crashed reading it (signal ") != std::string::npos ||
                    why.find("assimp's process ended before it finished") != std::string::npos ||
                    why.find("GridGrey.tga\": resolves to") != std::string::npos)
            << why;
    }
    EXPECT_TRUE(noChildLeft());
}

// What comes back from the child is what the same import made in this process: every OBJ, STL,
// PLY, FBX, COLLADA and 3MF file of assimp-testmodels and of tests/reference/assimp/ becomes the
// same glTF model (or the same refusal) either way. assimp's binary dump leaves out morph
// targets and channels and the scene's metadata, which travel beside it; this is what would show
// a field the conversion reads and the child does not send.
TEST(AssimpIsolated, EveryModelConvertsAsInProcess) {
    std::vector<std::string> files;
    // Joined by the preprocessor: GCC 12's link-time optimisation misreads a std::string
    // operator+ in this test body as an overflowing memcpy (-Wstringop-overflow).
    for (const char* root : {"/usr/share/assimp/models", RAYFARM_SOURCE_DIR "/tests/reference/assimp"}) {
        if (!std::filesystem::exists(root)) continue;
        for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
            std::string ext = e.path().extension().string();
            for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
            if (e.is_regular_file() && (ext == ".obj" || ext == ".stl" || ext == ".ply" || ext == ".fbx" || ext == ".dae" || ext == ".3mf"))
                files.push_back(e.path().string());
        }
    }
    if (files.size() < 20) GTEST_SKIP() << "assimp-testmodels not installed";
    std::sort(files.begin(), files.end());
    auto convert = [](const std::string& path, bool inProcess, std::vector<std::string>& notes, std::string& refusal) {
        if (inProcess) ::setenv("RAYFARM_TEST_ASSIMP_IN_PROCESS", "1", 1);
        else ::unsetenv("RAYFARM_TEST_ASSIMP_IN_PROCESS");
        DiskFileSource fs;
        tinygltf::Model m;
        try {
            m = importAssimpModel(path, fs, {}, notes);
        } catch (const InputError& e) {
            refusal = e.what();
        }
        ::unsetenv("RAYFARM_TEST_ASSIMP_IN_PROCESS");
        return m;
    };
    size_t compared = 0, refused = 0;
    for (const std::string& f : files) {
        if (f.find("assimp_crashes") != std::string::npos) continue;
        std::vector<std::string> notesHere, notesChild;
        std::string refusedHere, refusedChild;
        const tinygltf::Model here = convert(f, true, notesHere, refusedHere);
        const tinygltf::Model child = convert(f, false, notesChild, refusedChild);
        SCOPED_TRACE(f);
        EXPECT_EQ(refusedHere, refusedChild);
        EXPECT_EQ(notesHere, notesChild);
        EXPECT_TRUE(here.buffers == child.buffers);
        EXPECT_TRUE(here.accessors == child.accessors);
        EXPECT_TRUE(here.bufferViews == child.bufferViews);
        EXPECT_TRUE(here.nodes == child.nodes);
        EXPECT_TRUE(here.meshes == child.meshes);
        EXPECT_TRUE(here.materials == child.materials);
        EXPECT_TRUE(here.images == child.images);
        EXPECT_TRUE(here.textures == child.textures);
        EXPECT_TRUE(here.animations == child.animations);
        EXPECT_TRUE(here.skins == child.skins);
        EXPECT_TRUE(here == child);
        (refusedHere.empty() ? compared : refused) += 1;
    }
    std::printf("AssimpIsolated: %zu models the same in and out of process, %zu refused alike\n", compared, refused);
    EXPECT_GE(compared, 80u);
}

namespace {

void put64(std::string& m, uint64_t v) { m.append(reinterpret_cast<const char*>(&v), 8); }

/// A child's message around a real assimp dump of one triangle, its mesh's arrays as `meshes`
/// says (the bytes after the dump), with the length it states right.
std::string message(const std::string& afterDump, bool withScene = true) {
    static const std::string dump = [] {
        Assimp::Importer imp;
        const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        const aiScene* s = imp.ReadFileFromMemory(obj, sizeof obj - 1, 0, "obj");
        EXPECT_NE(s, nullptr);
        Assimp::Exporter ex;
        const aiExportDataBlob* b = s ? ex.ExportToBlob(s, "assbin") : nullptr;
        EXPECT_NE(b, nullptr);
        return b ? std::string(static_cast<const char*>(b->data), b->size) : std::string();
    }();
    std::string body(1, withScene ? '\1' : '\0');
    for (int i = 0; i < 5; ++i) put64(body, 0);  // the report's strings, empty
    put64(body, 0);                              // no files read
    put64(body, withScene ? dump.size() : 0);
    if (withScene) body += dump;
    body += afterDump;
    std::string m = "RFAI";
    put64(m, body.size());
    return m + body;
}

/// One mesh's header as takeMeshArrays writes it.
std::string meshHeader(uint64_t vertices, uint64_t present, uint64_t faces, uint64_t indices) {
    std::string h;
    put64(h, 1);  // one mesh
    put64(h, vertices);
    put64(h, present);
    for (int t = 0; t < 8; ++t) put64(h, 0);
    put64(h, faces);
    put64(h, indices);
    return h;
}

std::string readRefusal(const std::string& msg) {
    Assimp::Importer into;
    ChildImportReport report;
    try {
        readChildMessage(into, "model.obj", msg, report);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

// What the parent reads comes from a process that may have gone wrong in any way: short,
// malformed, or stating counts no message holds. Each is one InputError, found before anything
// is allocated for those counts.
TEST(AssimpIsolated, MalformedAnswersAreRefusedWithoutAllocatingTheirCounts) {
    EXPECT_NE(readRefusal(""), "");
    EXPECT_NE(readRefusal("RFAI"), "");
    EXPECT_NE(readRefusal(std::string(64, 'x')), "");
    std::string wrongLength = message("", false);
    wrongLength[4] ^= 1;
    EXPECT_NE(readRefusal(wrongLength), "");
    // A string as long as memory.
    std::string hugeString = "RFAI";
    std::string body(1, '\0');
    put64(body, uint64_t(1) << 62);
    put64(hugeString, body.size());
    EXPECT_NE(readRefusal(hugeString + body), "");
    // No scene: well formed, nullptr.
    {
        Assimp::Importer into;
        ChildImportReport report;
        EXPECT_EQ(readChildMessage(into, "model.obj", message("", false), report), nullptr);
    }
    // A dump without the mesh arrays, or with counts beyond the message: 2^62 indices (whose byte
    // count overflows), 2^31 vertices, a face with more indices than sent.
    EXPECT_NE(readRefusal(message("")), "");
    EXPECT_NE(readRefusal(message(meshHeader(3, 1, 1, uint64_t(1) << 62))), "");
    EXPECT_NE(readRefusal(message(meshHeader(uint64_t(1) << 31, 1, 1, 3))), "");
    std::string oneFace = meshHeader(3, 1, 1, 3) + std::string(36, '\0');
    uint32_t four = 4;
    oneFace.append(reinterpret_cast<const char*>(&four), 4);
    oneFace += std::string(12, '\0');
    EXPECT_NE(readRefusal(message(oneFace)), "");
    // The arrays right, then extras naming 2^32 - 1 morph targets: refused, not allocated.
    std::string arrays = meshHeader(3, 1, 1, 3) + std::string(36, '\0');
    uint32_t three = 3;
    arrays.append(reinterpret_cast<const char*>(&three), 4);
    for (uint32_t i = 0; i < 3; ++i) arrays.append(reinterpret_cast<const char*>(&i), 4);
    std::string extras;
    put64(extras, 0);  // no textures
    put64(extras, 1);  // one mesh
    put64(extras, 0);  // its name, empty
    put64(extras, UINT32_MAX);
    put64(extras, 0);
    const std::string why = readRefusal(message(arrays + extras));
    EXPECT_NE(why.find("malformed"), std::string::npos) << why;
    // And well formed: the triangle comes back.
    std::string fine;
    put64(fine, 0);
    put64(fine, 1);
    put64(fine, 0);
    put64(fine, 0);  // no targets
    put64(fine, 0);  // method
    put64(fine, 0);  // no animations
    Assimp::Importer into;
    ChildImportReport report;
    const aiScene* s = readChildMessage(into, "model.obj", message(arrays + fine), report);
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(s->mNumMeshes, 1u);
    EXPECT_EQ(s->mMeshes[0]->mNumVertices, 3u);
    EXPECT_EQ(s->mMeshes[0]->mNumFaces, 1u);
}
