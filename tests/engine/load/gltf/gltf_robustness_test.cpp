// Broken and foreign glTF files either render with finite pixels or are refused with an
// InputError naming the file: never a crash, hang, sanitizer report or non-finite pixel. Built
// with AddressSanitizer and UBSan by tests/run.sh (build-asan), and plainly in the main build.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/integrators/render.h"

using namespace rf;
namespace fs = std::filesystem;

namespace {

const std::string kRoot = "/usr/share/assimp/models/";

/// Every .gltf/.glb below dir, sorted so failures read the same on every run.
std::vector<std::string> modelsUnder(const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(kRoot + dir)) {
        const std::string ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".gltf" || ext == ".glb")) out.push_back(e.path().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

enum class Outcome { Rendered, Refused };

/// Loads and renders a small frame; returns how it ended, and fails the test on anything else.
Outcome loadAndRender(const std::string& path, std::string& message) {
    DiskFileSource files;
    try {
        Scene scene = loadGltfScene(path, files);
        RenderSettings s = scene.settings;
        s.width = 48;
        s.height = 27;
        RayStats stats;
        const Image img = renderFrame(scene, {scene.camera, s}, 0, 1, stats);
        for (int i = 0; i < img.width() * img.height() * 3; ++i)
            if (!std::isfinite(img.data()[i])) {
                ADD_FAILURE() << path << ": non-finite pixel value at " << i;
                break;
            }
        EXPECT_EQ(stats.nonFinite, 0u) << path << ": the tracer replaced non-finite samples";
        return Outcome::Rendered;
    } catch (const InputError& e) {
        message = e.what();
        EXPECT_EQ(message.rfind(path, 0), 0u) << "the message must start with the file: " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
        return Outcome::Refused;
    }
}

}  // namespace

TEST(GltfRobustness, BrokenGltf2FilesRenderOrAreRefused) {
    const char* broken[] = {"IndexOutOfRange", "wrongTypes", "BoxWithInfinites-glTF-Binary", "MissingBin", "RecursiveNodes",
                            "SchemaFailures", "TestNoRootNode", "IncorrectVertexArrays", "BoxBadNormals-glTF-Binary"};
    int files = 0, refused = 0;
    for (const char* dir : broken) {
        for (const std::string& path : modelsUnder(std::string("glTF2/") + dir)) {
            std::string msg;
            const Outcome o = loadAndRender(path, msg);
            ++files;
            refused += o == Outcome::Refused;
            std::printf("%-80s %s %s\n", path.c_str() + kRoot.size(), o == Outcome::Refused ? "refused:" : "rendered", msg.c_str());
        }
    }
    EXPECT_GE(files, 16);
    // These files are broken on purpose: at least the out-of-range indices and missing buffer
    // must be refused rather than drawn.
    EXPECT_GE(refused, 3);
}

TEST(GltfRobustness, MissingBufferAndOutOfRangeIndicesAreRefused) {
    for (const char* rel : {"glTF2/MissingBin/BoxTextured.gltf", "glTF2/IndexOutOfRange/IndexOutOfRange.gltf",
                            "glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf", "glTF2/RecursiveNodes/RecursiveNodes.gltf"}) {
        std::string msg;
        EXPECT_EQ(loadAndRender(kRoot + rel, msg), Outcome::Refused) << rel;
    }
}

TEST(GltfRobustness, EveryGltf1FileIsRefusedAsGltf1) {
    const std::vector<std::string> files = modelsUnder("glTF");
    ASSERT_GE(files.size(), 7u);
    for (const std::string& path : files) {
        std::string msg;
        EXPECT_EQ(loadAndRender(path, msg), Outcome::Refused) << path;
        EXPECT_NE(msg.find("glTF 1.0"), std::string::npos) << path << ": " << msg;
    }
}

TEST(GltfRobustness, OtherShippedGltf2FilesLoadOrAreRefused) {
    // The rest of the package (draco, skins, extensions, asset generator): same contract.
    for (const char* dir : {"glTF2/draco", "glTF2/simple_skin", "glTF2/issue_3269", "glTF2/BoxTexcoords-glTF",
                            "glTF2/BoxTextured-glTF-pbrSpecularGlossiness", "glTF2/BoxTextured-glTF-techniqueWebGL",
                            "glTF2/glTF-Asset-Generator"}) {
        for (const std::string& path : modelsUnder(dir)) {
            std::string msg;
            const Outcome o = loadAndRender(path, msg);
            std::printf("%-80s %s %s\n", path.c_str() + kRoot.size(), o == Outcome::Refused ? "refused:" : "rendered", msg.c_str());
        }
    }
}

TEST(GltfRobustness, CorruptedBinaryModelsAreRefusedOrRendered) {
    // Deterministic corruptions of a real .glb: truncations and byte flips anywhere in the JSON
    // and BIN chunks (lengths, offsets, indices, floats). Each must end in one of the two
    // allowed outcomes; under the sanitizers any out-of-bounds read fails the run.
    const std::string src = kRoot + "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
    std::ifstream in(src, std::ios::binary);
    const std::string original((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(original.size(), 1000u);
    const fs::path dir = fs::temp_directory_path() / ("rayfarm-gltf-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    uint64_t state = 0x9E3779B97F4A7C15ull;
    auto next = [&] {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return state;
    };
    int rendered = 0, refused = 0;
    for (int k = 0; k < 320; ++k) {
        std::string bytes = original;
        if (k % 4 == 0) {
            bytes.resize(next() % bytes.size());
        } else {
            const int flips = 1 + int(next() % 4);
            for (int f = 0; f < flips; ++f) bytes[next() % bytes.size()] = char(next());
        }
        std::string name = "m";
        name += std::to_string(k);
        name += ".glb";
        const std::string path = (dir / name).string();
        std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        std::string msg;
        (loadAndRender(path, msg) == Outcome::Rendered ? rendered : refused)++;
    }
    fs::remove_all(dir);
    std::printf("corrupted BoxTextured.glb: %d rendered, %d refused\n", rendered, refused);
    EXPECT_EQ(rendered + refused, 320);
    EXPECT_GT(refused, 40);  // truncations alone are a quarter of the cases
}
