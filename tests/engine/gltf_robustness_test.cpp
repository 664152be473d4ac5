// Broken and foreign glTF files either render with finite pixels or are refused with an
// InputError naming the file: never a crash, hang, sanitizer report or non-finite pixel. Built
// with AddressSanitizer and UBSan by tests/run.sh (build-asan), and plainly in the main build.
#include <gtest/gtest.h>

#include <filesystem>

#include "errors.h"
#include "gltf_loader.h"
#include "render.h"

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
        const Image img = renderFrame(scene, scene.camera, s, 0, 1, stats);
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
