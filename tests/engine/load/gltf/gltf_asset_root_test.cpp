// Asset folders: a glTF URI may leave the model's folder while it stays inside the asset root
// (--asset-root, the scene file's "asset_root", else the current directory when the model lies
// under it, else the model's folder); outside it, through a symbolic link or as an absolute path
// it is refused with a message naming --asset-root.
#include <gtest/gtest.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/load/scene_loader.h"

using namespace rf;
using namespace gltftest;

namespace {

std::string triangle() {
    float a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    return oneTriangleBytes(a, b, c);
}

/// root/models/m.gltf reading `uri`; root/common/tri.bin and root/../outside-<n>/tri.bin exist.
struct Layout {
    TempDir root, outside;
    std::string model;
    explicit Layout(const std::string& uri) {
        writeFile(root / "common/tri.bin", triangle());
        writeFile(outside / "tri.bin", triangle());
        model = root / "models/m.gltf";
        writeFile(model, oneTriangleGltf(uri).dump());
    }
};

std::string loadError(const std::string& path, const AssetOptions& assets) {
    DiskFileSource files;
    Scene scene;
    try {
        loadGltfModel(scene, path, DMat4(1.0), files, -1, assets);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

size_t loadedMeshes(const std::string& path, const AssetOptions& assets) {
    DiskFileSource files;
    Scene scene;
    loadGltfModel(scene, path, DMat4(1.0), files, -1, assets);
    return scene.geometry.meshes.size();
}

/// Runs in `dir` as the current directory, then goes back.
struct InDirectory {
    fs::path old = fs::current_path();
    explicit InDirectory(const fs::path& dir) { fs::current_path(dir); }
    ~InDirectory() { fs::current_path(old); }
};

}  // namespace

TEST(GltfAssetRoot, UriInsideTheRootLoadsAndOutsideItIsRefused) {
    Layout l("../common/tri.bin");
    AssetOptions inside;
    inside.root = l.root.path.string();
    EXPECT_EQ(loadedMeshes(l.model, inside), 1u);
    // The default root of a model outside the current directory is its own folder.
    ASSERT_NE(fs::current_path().string().rfind(l.root.path.string(), 0), 0u);
    const std::string e = loadError(l.model, {});
    EXPECT_NE(e.find("outside the asset root"), std::string::npos) << e;
    EXPECT_NE(e.find("--asset-root"), std::string::npos) << e;
    EXPECT_EQ(e.rfind(l.model, 0), 0u) << e;
}

TEST(GltfAssetRoot, UriLeavingTheRootIsRefusedEvenWithARoot) {
    Layout l("x");
    writeFile(l.model, oneTriangleGltf("../../" + l.outside.path.filename().string() + "/tri.bin").dump());
    AssetOptions opts;
    opts.root = l.root.path.string();
    const std::string e = loadError(l.model, opts);
    EXPECT_NE(e.find("--asset-root"), std::string::npos) << e;
    // Control: the same URI loads once the root takes in both folders.
    opts.root = l.root.path.parent_path().string();
    EXPECT_EQ(loadedMeshes(l.model, opts), 1u);
}

TEST(GltfAssetRoot, SymbolicLinkOutOfTheRootIsRefused) {
    Layout l("link.bin");
    fs::create_symlink(l.outside / "tri.bin", l.root / "models/link.bin");
    AssetOptions opts;
    opts.root = l.root.path.string();
    const std::string e = loadError(l.model, opts);
    EXPECT_NE(e.find("outside the asset root"), std::string::npos) << e;
    // A link that stays inside the root is followed.
    fs::remove(l.root / "models/link.bin");
    fs::create_symlink(l.root / "common/tri.bin", l.root / "models/link.bin");
    EXPECT_EQ(loadedMeshes(l.model, opts), 1u);
    // A linked folder on the way out is caught as well.
    Layout l2("sub/tri.bin");
    fs::create_directory_symlink(l2.outside.path, l2.root / "models/sub");
    opts.root = l2.root.path.string();
    EXPECT_NE(loadError(l2.model, opts).find("outside the asset root"), std::string::npos);
}

TEST(GltfAssetRoot, AbsoluteUriIsRefusedNamingTheOption) {
    Layout l("x");
    writeFile(l.model, oneTriangleGltf(l.root / "common/tri.bin").dump());
    AssetOptions opts;
    opts.root = "/";
    const std::string e = loadError(l.model, opts);
    EXPECT_NE(e.find("absolute paths are not allowed"), std::string::npos) << e;
    EXPECT_NE(e.find("--asset-root"), std::string::npos) << e;
}

TEST(GltfAssetRoot, DefaultRootIsTheCurrentDirectoryWhenTheModelLiesUnderIt) {
    Layout l("../common/tri.bin");
    InDirectory cd(l.root.path);
    EXPECT_EQ(loadedMeshes("models/m.gltf", {}), 1u);
    EXPECT_EQ(loadedMeshes(l.model, {}), 1u);  // the absolute path lies under it as well
    InDirectory deeper(l.root.path / "models");
    EXPECT_NE(loadError("m.gltf", {}).find("--asset-root"), std::string::npos);
}

TEST(GltfAssetRoot, SceneFileKeySetsTheRootAndTheCommandLineOverridesIt) {
    Layout l("../common/tri.bin");
    const std::string scene = l.root / "scene.json";
    const json objects = {{{"type", "model"}, {"path", "models/m.gltf"}}};
    writeFile(scene, json{{"asset_root", "."}, {"objects", objects}}.dump());
    auto load = [&](const SceneOptions& o = {}) {
        DiskFileSource files;  // a fresh one each time: it keeps what it read
        return loadScene(scene, files, o).scene;
    };
    EXPECT_EQ(load().geometry.meshes.size(), 1u);
    // Without the key the model's folder is the root: refused.
    writeFile(scene, json{{"objects", objects}}.dump());
    try {
        load();
        ADD_FAILURE() << "loaded without asset_root";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--asset-root"), std::string::npos) << e.what();
    }
    // --asset-root beats the file's key.
    writeFile(scene, json{{"asset_root", "models"}, {"objects", objects}}.dump());
    SceneOptions o;
    o.assets.root = l.root.path.string();
    o.rootFromCommandLine = true;
    EXPECT_EQ(load(o).geometry.meshes.size(), 1u);
    EXPECT_THROW(load(), InputError);  // the key alone (models/) is too narrow
}
