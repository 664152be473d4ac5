// A pixel is a function of (scene, frame, pixel, sample) only. Whatever a thread carries from
// pixel to pixel (the cache of each light's last blocker, the camera-ray packets, the tile it
// was handed) may make a result faster, never different: the same frame rendered with tile
// sizes 1, 7, 16, 32 and 128, packets on and off, the blocker cache on and off, on 1 and 2
// threads, is the same to the bit (linear floats and encoded bytes). The bounce cache
// (bounce_cache.h) is a function of the scene alone: built on one thread or two, the same.
#include <gtest/gtest.h>

#include <cstring>

#include "engine/integrators/bounce_cache.h"
#include "tests/engine/engine_test_util.h"
#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "farm/report/stability/stability_scenes.h"

using namespace rf;

namespace {

const std::string kAssimp = "/usr/share/assimp/models/glTF2/";

struct Variant {
    int tileSize;
    bool packets, blockerCache;
    int threads;
};

/// Renders `scene` as every variant and expects each to equal the first, float for float.
/// bounce: the film's bounce cache, shared by the variants on two threads (null: a new one).
void expectIdenticalAcrossVariants(const std::string& name, const Scene& scene, RenderSettings s,
                                   std::shared_ptr<SceneCacheSlot> bounce = nullptr) {
    std::vector<Variant> variants;
    for (int tile : {32, 1, 7, 16, 128})
        for (bool packets : {true, false}) variants.push_back({tile, packets, true, 2});
    variants.push_back({16, true, false, 2});
    variants.push_back({7, false, false, 1});
    variants.push_back({128, true, true, 1});
    std::vector<float> first;
    std::vector<uint8_t> firstBytes;
    const auto shared = bounce ? bounce : std::make_shared<SceneCacheSlot>();
    for (const Variant& v : variants) {
        s.tileSize = v.tileSize;
        s.packets = v.packets;
        s.blockerCache = v.blockerCache;
        RayStats rays;
        // On one thread the bounce cache is built afresh, on that thread alone (the other
        // variants share the one the first built on two).
        const auto slot = v.threads == 1 ? std::make_shared<SceneCacheSlot>() : shared;
        const Image img = renderFrame(scene, {scene.camera, s, slot}, 3, v.threads, rays);
        const std::vector<float> px(img.data(), img.data() + size_t(img.width()) * img.height() * 3);
        const std::vector<uint8_t> bytes = toRgb8(img, s);
        if (first.empty()) {
            first = px;
            firstBytes = bytes;
            continue;
        }
        size_t differ = 0;
        for (size_t i = 0; i < px.size(); ++i) differ += std::memcmp(&px[i], &first[i], sizeof(float)) != 0;
        EXPECT_EQ(differ, 0u) << name << ": tile " << v.tileSize << ", packets " << v.packets << ", blocker cache "
                              << v.blockerCache << ", " << v.threads << " threads: floats differ from tile 32";
        EXPECT_TRUE(bytes == firstBytes) << name << ": tile " << v.tileSize << ", packets " << v.packets;
    }
}

RenderSettings small(const Scene& scene, int spp) {
    RenderSettings s = scene.settings;
    s.width = 80;
    s.height = 45;
    s.spp = spp;
    s.autoExposure = false;
    s.exposure = 0.f;
    return s;
}

}  // namespace

// 121k triangles casting shadows on themselves under the default look (studio environment,
// default light rig): the blocker cache is busiest here. With the shadow-catcher ground too.
TEST(PixelIndependence, EngineModelIsTheSameAtEveryTilingPacketAndCache) {
    DiskFileSource fs;
    SceneOptions o;
    o.ground = Ground::Shadow;
    const LoadedScene sceneLoaded = loadScene(kAssimp + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb", fs, o);
    const Scene& scene = sceneLoaded.scene;
    expectIdenticalAcrossVariants("2CylinderEngine", scene, small(scene, 4));
}

// The flat quads that self-shadowed per tile, textured, with their decals.
TEST(PixelIndependence, FlatTexturedQuadsAreTheSameAtEveryTilingPacketAndCache) {
    DiskFileSource fs;
    const LoadedScene sceneLoaded = loadScene(kAssimp + "textureTransform/TextureTransformTest.gltf", fs);
    const Scene& scene = sceneLoaded.scene;
    expectIdenticalAcrossVariants("TextureTransformTest", scene, small(scene, 4));
}

// A floor of two big triangles just above y = 0 (where shadow rays used to meet their own floor)
// under a smooth-shaded sphere mesh and a point light: shadows, self-shadowing and the
// terminator shift, the floor and the ball in the same BVH leaves.
TEST(PixelIndependence, MeshFloorUnderAMeshBallIsTheSameAtEveryTilingPacketAndCache) {
    Scene s = test::emptyScene();
    s.materials[0] = test::matte(Color(0.8f), 0.f, 1.f);
    TriangleMesh floor;
    floor.positions = {Vec3(-50, 1e-3f, -50), Vec3(50, 1e-3f, -50), Vec3(50, 1e-3f, 50), Vec3(-50, 1e-3f, 50)};
    floor.indices = {0, 2, 1, 0, 3, 2};
    s.geometry.meshes.push_back(floor);
    s.geometry.meshes.push_back(test::uvSphere(12, 24, 1.f, Vec3(0.f, 1.2f, 0.f), true));
    Light l;
    l.position = Vec3(3.f, 6.f, 2.f);
    s.lights = {l};
    s.camera.eye = Vec3(0.f, 3.f, 8.f);
    s.camera.target = Vec3(0.f, 0.8f, 0.f);
    s.build();
    expectIdenticalAcrossVariants("mesh floor and ball", s, small(s, 4));
}

// Spheres, a plane, Phong, mirrors (the scene-file model), and glTF glass, metals and sampled
// indirect light (pbr_grid with --indirect 2: random numbers from the work item).
TEST(PixelIndependence, WhittedAndSampledIndirectAreTheSameAtEveryTilingPacketAndCache) {
    const Scene demo = stability::demoScene(1.f);
    expectIdenticalAcrossVariants("demo scene", demo, small(demo, 4));
    DiskFileSource fs;
    LoadedScene gridLoaded = loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/pbr_grid/pbr_grid.gltf", fs);
    Scene& grid = gridLoaded.scene;
    useGltfCamera(grid, 0);
    RenderSettings s = small(grid, 1);
    s.indirectSamples = 2;
    expectIdenticalAcrossVariants("pbr_grid --indirect 2", grid, s);
}

// The default look's bounce light, cached per film: the lights' bounce off the floor and the
// spheres, the same at every tiling and whichever thread count built the cache.
TEST(PixelIndependence, BounceLightIsTheSameAtEveryTilingPacketAndCache) {
    DiskFileSource fs;
    LoadedScene gridLoaded = loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/pbr_grid/pbr_grid.gltf", fs);
    Scene& grid = gridLoaded.scene;
    useGltfCamera(grid, 0);
    const RenderSettings s = small(grid, 1);
    ASSERT_GT(s.bounce, 0);
    const auto slot = std::make_shared<SceneCacheSlot>();
    ASSERT_TRUE(bounceCache(grid, s, slot.get(), 2));
    expectIdenticalAcrossVariants("pbr_grid bounce", grid, s, slot);
}
