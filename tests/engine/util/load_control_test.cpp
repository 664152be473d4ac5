// Issue 30 #3: loading answers signals. The farm's handler calls requestLoadCancel; each part of
// a load (JSON parse, scene objects, glTF, textures, the environment's filtering, the BVH) stops
// at its next poll with LoadCancelled naming what it was doing, and loadScene adds the file. A
// render's BVH rebuild (posing) never stops. Real processes and signals: tests/farm/cluster/
// load_signal_test.sh.
#include <gtest/gtest.h>

#include <csignal>
#include <new>

#include "engine/geometry/bvh.h"
#include "engine/scene/env_lighting.h"
#include "engine/util/errors.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/util/json_guard.h"
#include "engine/util/load_control.h"
#include "engine/load/scene_loader.h"

using namespace rf;
using namespace gltftest;

namespace {

/// A cancel asked for by "SIGTERM" for the scope of one test.
struct Cancelled {
    Cancelled() { requestLoadCancel(SIGTERM); }
    ~Cancelled() { requestLoadCancel(0); }
};

/// What f threw as LoadCancelled; signal 0 if it did not.
template <class F>
LoadCancelled cancelOf(F&& f) {
    try {
        f();
    } catch (const LoadCancelled& c) {
        return c;
    }
    return {};
}

/// A scene file of n spheres on a line, none touching.
std::string spheresScene(int n) {
    std::string s = R"({"camera": {"eye": [0, 0, 10], "target": [0, 0, 0]}, "objects": [)";
    for (int i = 0; i < n; ++i) {
        if (i) s += ',';
        s += R"({"type": "sphere", "center": [)" + std::to_string(3 * i) + R"(, 0, 0], "radius": 1})";
    }
    return s + "]}";
}

}  // namespace

TEST(LoadControl, AJsonParseStopsNamingItsStep) {
    const std::string text = spheresScene(20000);
    ASSERT_NO_THROW(parseUserJson("s.json", text));
    Cancelled c;
    const LoadCancelled got = cancelOf([&] { parseUserJson("s.json", text); });
    EXPECT_EQ(got.signal, SIGTERM);
    EXPECT_EQ(got.step, "parsing its JSON");
}

TEST(LoadControl, LoadSceneStopsAndNamesTheFile) {
    TempDir dir;
    writeFile(dir / "s.json", spheresScene(5000));
    DiskFileSource fs;
    EXPECT_EQ(loadScene(dir / "s.json", fs).scene.geometry.spheres.size(), 5000u);
    Cancelled c;
    DiskFileSource fs2;
    const LoadCancelled got = cancelOf([&] { loadScene(dir / "s.json", fs2); });
    EXPECT_EQ(got.signal, SIGTERM);
    EXPECT_EQ(got.file, dir / "s.json");
    EXPECT_EQ(got.step, "parsing its JSON");
}

TEST(LoadControl, TheBvhBuildStopsOnlyWhenALoadBuildsIt) {
    std::vector<Aabb> boxes(50000);
    for (size_t i = 0; i < boxes.size(); ++i) {
        boxes[i].lo = Vec3(float(i), 0.f, 0.f);
        boxes[i].hi = Vec3(float(i) + 0.5f, 1.f, 1.f);
    }
    Cancelled c;
    Bvh bvh;
    EXPECT_EQ(cancelOf([&] { bvh.build(boxes, 4, true); }).signal, SIGTERM);
    // Posing rebuilds the tree while frames render: that must finish whatever the flag says.
    ASSERT_NO_THROW(bvh.build(boxes));
    EXPECT_FALSE(bvh.empty());
}

TEST(LoadControl, EnvironmentFilteringStops) {
    EquirectImage img;
    img.width = 512;
    img.height = 256;
    img.texels.assign(size_t(img.width) * img.height, Color(1.f));
    Cancelled c;
    const LoadCancelled got = cancelOf([&] { EnvironmentLight env(img, 0.f, 1.f, 2); });
    EXPECT_EQ(got.signal, SIGTERM);
    EXPECT_EQ(got.step, "filtering the environment");
}

TEST(LoadControl, AGltfLoadStops) {
    Cancelled c;
    DiskFileSource fs;
    const std::string box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    const LoadCancelled got = cancelOf([&] { loadScene(box, fs); });
    EXPECT_EQ(got.signal, SIGTERM);
    EXPECT_EQ(got.file, box);
}

// A failure names the innermost step it unwound through, though that step's scope has closed
// by the time the handler runs; a later step starts clean.
TEST(LoadControl, AFailureNamesTheInnermostStep) {
    try {
        LoadStep outer("reading the scene");
        LoadStep inner("building the BVH");
        throw std::bad_alloc();
    } catch (const std::bad_alloc&) {
        EXPECT_STREQ(lastFailedStep(), "building the BVH");
    }
    LoadStep next("decoding its textures");
    EXPECT_STREQ(lastFailedStep(), "decoding its textures");
    EXPECT_STREQ(currentLoadStep(), "decoding its textures");
    EXPECT_EQ(std::string(OutOfMemoryError("big\n.json", "building the BVH").what()),
              "big\\n.json: out of memory while building the BVH");
}
