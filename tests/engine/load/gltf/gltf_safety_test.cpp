// URI confinement and caps of the glTF loader: buffer and image URIs resolve inside the model's
// folder only, nothing outside is read (every read goes through a recording FileSource), and no
// shell expansion happens.
#include <gtest/gtest.h>

#include <set>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/gltf/gltf_safety.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
using namespace gltftest;

namespace {

/// Disk access that records every path the loader asks about.
class RecordingFileSource : public FileSource {
public:
    std::string read(const std::string& path, uint64_t maxBytes) override {
        touched.insert(path);
        return disk.read(path, maxBytes);
    }
    bool exists(const std::string& path) override {
        touched.insert(path);
        return disk.exists(path);
    }
    std::set<std::string> touched;
    DiskFileSource disk;
};

bool inside(const std::string& path, const fs::path& folder) {
    const fs::path p = fs::weakly_canonical(fs::absolute(path));
    const fs::path f = fs::weakly_canonical(folder);
    auto [a, b] = std::mismatch(f.begin(), f.end(), p.begin(), p.end());
    return a == f.end();
}

/// Loads the model and expects an InputError whose message contains `needle`.
void expectRefused(const std::string& path, FileSource& files, const std::string& needle) {
    Scene scene;
    try {
        loadGltfModel(scene, path, DMat4(1.0), files);
        ADD_FAILURE() << path << " loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}

std::string triangle() {
    float a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    return oneTriangleBytes(a, b, c);
}

}  // namespace

TEST(GltfSafety, UriProblemAcceptsOnlyPlainRelativePaths) {
    EXPECT_EQ(gltf::uriProblem("buffer.bin"), "");
    // ".." is syntax like any other; the asset root confines where it leads (gltf_asset_root_test).
    EXPECT_EQ(gltf::uriProblem("../textures/wall.png"), "");
    EXPECT_EQ(gltf::uriProblem("sub/dir/buffer 1.bin"), "");
    EXPECT_EQ(gltf::uriProblem("a..b.bin"), "");  // dots inside a name are fine
    EXPECT_EQ(gltf::uriProblem("rock&roll (1).png"), "");
    for (const char* bad : {"/etc/passwd", "~/x.bin", "`touch x`.bin", "$(touch x).bin",
                            "${HOME}/x.bin", "file:///etc/passwd", "http://example.com/x.bin", "C:\\x.bin", "a*b.bin", ""})
        EXPECT_NE(gltf::uriProblem(bad), "") << bad;
    EXPECT_EQ(gltf::decodeUri("%2e%2e/x+y.bin"), "../x y.bin");
    // Each character of shell syntax is named in the message (one literal each, issue 47).
    // Compared in pieces: a long message grown around the character trips GCC 12's LTO warning.
    for (const char c : std::string("`$\\*?{}")) {
        std::string uri = "a";
        uri += c;
        uri += "b.bin";
        const std::string why = gltf::uriProblem(uri);
        EXPECT_EQ(why.rfind("character '", 0), 0u) << why;
        EXPECT_EQ(why.substr(11, 1), std::string(1, c)) << why;
        EXPECT_EQ(why.substr(12), "' is not allowed in a file URI (no shell syntax)") << why;
    }
}

TEST(GltfSafety, EscapingBufferUrisAreRefusedAndNothingOutsideIsRead) {
    TempDir root;
    const fs::path modelDir = root.path / "model";
    writeFile(root / "outside/secret.bin", triangle());  // a valid buffer the model must not reach
    writeFile(root / "model/ok.bin", triangle());
    const std::string secretAbs = root / "outside/secret.bin";
    const std::vector<std::string> uris = {"../outside/secret.bin", "../../etc/passwd", "/etc/passwd", secretAbs,
                                           "%2e%2e/outside/secret.bin", "sub/../../outside/secret.bin", "`touch PWNED`.bin",
                                           "$(touch PWNED).bin", "~/secret.bin", "file://" + secretAbs};
    const fs::path cwd = fs::current_path();
    for (size_t i = 0; i < uris.size(); ++i) {
        const std::string path = root / ("model/m" + std::to_string(i) + ".gltf");
        writeFile(path, oneTriangleGltf(uris[i]).dump());
        RecordingFileSource files;
        Scene scene;
        try {
            loadGltfModel(scene, path, DMat4(1.0), files);
            ADD_FAILURE() << uris[i] << ": loaded";
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
        }
        for (const std::string& t : files.touched) EXPECT_TRUE(inside(t, modelDir)) << uris[i] << " made the loader touch " << t;
        EXPECT_TRUE(scene.geometry.meshes.empty());
    }
    EXPECT_FALSE(fs::exists(modelDir / "PWNED"));
    EXPECT_FALSE(fs::exists(cwd / "PWNED"));
    EXPECT_FALSE(fs::exists(root.path / "PWNED"));

    // Positive control: the same model with a URI inside its folder loads and reads only that.
    const std::string okPath = root / "model/ok.gltf";
    writeFile(okPath, oneTriangleGltf("ok.bin").dump());
    RecordingFileSource files;
    Scene scene;
    loadGltfModel(scene, okPath, DMat4(1.0), files);
    ASSERT_EQ(scene.geometry.meshes.size(), 1u);
    EXPECT_EQ(scene.geometry.meshes[0].positions[1], Vec3(1, 0, 0));
    for (const std::string& t : files.touched) EXPECT_TRUE(inside(t, modelDir)) << t;
}

TEST(GltfSafety, EscapingImageUriIsRefused) {
    TempDir root;
    writeFile(root / "outside/logo.png", readFile("/usr/share/assimp/models/glTF2/BoxTextured-glTF/CesiumLogoFlat.png"));
    json g = oneTriangleGltf(dataUri(triangle()));
    g["images"] = {{{"uri", "../outside/logo.png"}}};
    const std::string path = root / "model/img.gltf";
    writeFile(path, g.dump());
    RecordingFileSource files;
    Scene scene;
    EXPECT_THROW(loadGltfModel(scene, path, DMat4(1.0), files), InputError);
    for (const std::string& t : files.touched) EXPECT_TRUE(inside(t, root.path / "model")) << t;
}

TEST(GltfSafety, OversizedBufferIsRefusedBeforeReading) {
    TempDir root;
    json g = oneTriangleGltf("big.bin");
    g["buffers"][0]["byteLength"] = 8ull << 30;
    const std::string path = root / "big.gltf";
    writeFile(path, g.dump());
    RecordingFileSource files;
    expectRefused(path, files, "limit");
    EXPECT_EQ(files.touched.count(root / "big.bin"), 0u);
}

TEST(GltfSafety, AccessorPastItsBufferViewIsRefused) {
    TempDir root;
    json g = oneTriangleGltf(dataUri(triangle()));
    g["accessors"][0]["count"] = 4;  // 48 bytes from a 36-byte view
    const std::string path = root / "long.gltf";
    writeFile(path, g.dump());
    DiskFileSource files;
    expectRefused(path, files, "accessors[0]");
    g["accessors"][0]["count"] = 3;
    g["bufferViews"][0]["byteOffset"] = 4;  // view runs past its 36-byte buffer
    writeFile(path, g.dump());
    Scene scene;
    EXPECT_THROW(loadGltfModel(scene, path, DMat4(1.0), files), InputError);
}

TEST(GltfSafety, HugeAccessorWithoutBufferViewIsRefused) {
    // 30 million zero vectors (360 MB of floats) asked for by a few bytes of JSON: refused.
    TempDir root;
    json g = oneTriangleGltf(dataUri(triangle()));
    g["accessors"][0].erase("bufferView");
    g["accessors"][0]["count"] = 30000000;  // under the general cap, over the view-less one
    const std::string path = root / "huge.gltf";
    writeFile(path, g.dump());
    DiskFileSource files;
    expectRefused(path, files, "over the limit");
}

TEST(GltfSafety, InstancingPastTheTriangleCapIsRefusedBeforeBuilding) {
    // One 4M-vertex zero accessor drawn by 30 nodes: 40M triangles, over the 32M cap.
    TempDir root;
    json g = oneTriangleGltf(dataUri(triangle()));
    g["accessors"][0].erase("bufferView");
    g["accessors"][0]["count"] = 4000002;
    json nodes = json::array(), roots = json::array();
    for (int i = 0; i < 30; ++i) {
        nodes.push_back({{"mesh", 0}, {"translation", {i, 0, 0}}});
        roots.push_back(i);
    }
    g["nodes"] = nodes;
    g["scenes"][0]["nodes"] = roots;
    const std::string path = root / "many.gltf";
    writeFile(path, g.dump());
    DiskFileSource files;
    expectRefused(path, files, "instance");
}

TEST(GltfSafety, WorkerRanksLoadTheSameModelFromTheBundle) {
    // Rank 0 reads from disk and records; other ranks see only the bundle.
    const std::string path = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    DiskFileSource disk;
    const Scene a = loadGltfScene(path, disk);
    EXPECT_EQ(disk.bundle().files.size(), 3u);  // .gltf, .bin and the texture
    BundleFileSource bundle(FileBundle::deserialize(disk.bundle().serialize()));
    const Scene b = loadGltfScene(path, bundle);
    ASSERT_EQ(a.geometry.meshes.size(), b.geometry.meshes.size());
    EXPECT_EQ(a.geometry.meshes[0].positions, b.geometry.meshes[0].positions);
    EXPECT_EQ(a.textures.size(), 1u);
    ASSERT_EQ(b.textures.size(), 1u);
    EXPECT_EQ(a.textures[0].texels, b.textures[0].texels);
}
