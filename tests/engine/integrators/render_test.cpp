// The tile renderer: bit-identical output for any thread count and tile size, renderTile as
// the one entry point, and the NaN/Inf firewall (catalogue 19).
#include <gtest/gtest.h>

#include <cstring>

#include "tests/engine/engine_test_util.h"
#include "engine/util/sampler.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {
LoadedScene whitted() {
    DiskFileSource fs;
    return loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", fs);
}
bool sameBits(const Image& a, const Image& b) {
    return a.width() == b.width() && a.height() == b.height() &&
           std::memcmp(a.data(), b.data(), sizeof(float) * 3 * a.width() * a.height()) == 0;
}
}  // namespace

TEST(Render, BitIdenticalForAnyThreadCountAndTileSize) {
    const LoadedScene sLoaded = whitted();
    const Scene& s = sLoaded.scene;
    RenderSettings rs = test::smallSettings(97, 61, 4, 5);  // odd sizes: partial tiles at the edges
    RayStats s1, s2, s3;
    rs.tileSize = 16;
    const Image one = renderFrame(s, {s.camera, rs}, 7, 1, s1);
    const Image two = renderFrame(s, {s.camera, rs}, 7, 2, s2);
    const Image three = renderFrame(s, {s.camera, rs}, 7, 3, s3);
    EXPECT_TRUE(sameBits(one, two));
    EXPECT_TRUE(sameBits(one, three));
    EXPECT_EQ(s1.total(), s2.total());
    EXPECT_EQ(s1.total(), s3.total());
    for (int tile : {1, 7, 32, 200}) {
        rs.tileSize = tile;
        RayStats st;
        EXPECT_TRUE(sameBits(one, renderFrame(s, {s.camera, rs}, 7, 2, st))) << "tile " << tile;
    }
    // Another frame index draws other jitter: the picture is a function of the frame too.
    RayStats st;
    rs.tileSize = 16;
    EXPECT_FALSE(sameBits(one, renderFrame(s, {s.camera, rs}, 8, 2, st)));
}

// Camera rays go through the BVH in packets of aligned pixel blocks: tiles of any size, odd
// rectangles and thread counts must still give every pixel the same bits, with the rays
// counted once. A triangle scene (sphere and grid meshes, so the BVH is used) at 4 spp.
TEST(Render, PacketsGiveTheSamePixelsForAnyTiling) {
    Scene s = test::emptyScene();
    s.materials[0] = test::matte(Color(0.8f, 0.5f, 0.3f));
    s.geometry.meshes.push_back(test::uvSphere(24, 48, 1.f, Vec3(0, 1, 0), true));
    s.geometry.meshes.push_back(test::gridMesh(16, 4.f));
    s.lights.push_back(Light{});
    s.lights.back().position = Vec3(3, 5, -4);
    s.camera.eye = Vec3(0.3f, 2.f, -5.f);
    s.camera.target = Vec3(0, 0.8f, 0);
    s.build();
    ASSERT_TRUE(s.geometry.usesBvh());
    RenderSettings rs = test::smallSettings(83, 45, 4, 3);
    rs.tileSize = 32;
    RayStats ref;
    const Image one = renderFrame(s, {s.camera, rs}, 3, 1, ref);
    EXPECT_EQ(ref.primary, uint64_t(83 * 45 * 4));
    for (int tile : {1, 3, 7, 16, 64}) {
        rs.tileSize = tile;
        RayStats st;
        EXPECT_TRUE(sameBits(one, renderFrame(s, {s.camera, rs}, 3, 2, st))) << "tile " << tile;
        EXPECT_EQ(st.total(), ref.total()) << "tile " << tile;
    }
    const TileRect rect{5, 3, 62, 38};
    std::vector<float> buf(size_t(rect.pixels()) * 3);
    RayStats ts;
    renderTile(s, {s.camera, rs}, rect, 3, buf.data(), ts);
    EXPECT_EQ(ts.primary, uint64_t(rect.pixels()) * 4);
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(buf[3 * ((y - rect.y0) * rect.width() + (x - rect.x0)) + c], one.pixel(x, y)[c]) << x << "," << y;
}

TEST(Render, RenderTileMatchesTheFrameRegion) {
    const LoadedScene sLoaded = whitted();
    const Scene& s = sLoaded.scene;
    const RenderSettings rs = test::smallSettings(64, 40, 1, 5);
    RayStats st;
    const Image frame = renderFrame(s, {s.camera, rs}, 0, 2, st);
    const TileRect rect{13, 5, 41, 29};
    std::vector<float> buf(size_t(rect.pixels()) * 3);
    RayStats ts;
    renderTile(s, {s.camera, rs}, rect, 0, buf.data(), ts);
    EXPECT_EQ(ts.primary, uint64_t(rect.pixels()));
    for (int y = rect.y0; y < rect.y1; ++y)
        for (int x = rect.x0; x < rect.x1; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(buf[3 * ((y - rect.y0) * rect.width() + (x - rect.x0)) + c], frame.pixel(x, y)[c]);
    // Tiles cover the image exactly once.
    std::vector<int> cover(64 * 40, 0);
    for (const TileRect& t : makeTiles(64, 40, 24))
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) ++cover[y * 64 + x];
    for (int c : cover) ASSERT_EQ(c, 1);
}

// Catalogue 19: NaN and Inf radiance (an emissive material of +inf, a NaN colour) never reach
// the image; every affected sample is counted.
TEST(Render, NonFiniteRadianceIsReplacedAndCounted) {
    Scene s = test::emptyScene();
    Material hot = test::matte(Color(0.5f));
    hot.emission = Color(std::numeric_limits<float>::infinity(), 0.f, 0.f);
    Material nan = test::matte(Color(std::nanf(""), 0.5f, 0.5f));
    s.materials = {test::matte(Color(0.5f)), hot, nan};
    s.geometry.spheres.push_back(Sphere{Vec3(-1.2f, 0.f, 0.f), 1.f, 1});
    s.geometry.spheres.push_back(Sphere{Vec3(1.2f, 0.f, 0.f), 1.f, 2});
    Light l;
    l.position = Vec3(0, 5, 5);
    s.lights.push_back(l);
    s.camera.eye = Vec3(0, 0, 6);
    s.camera.fovDeg = 50.f;
    s.build();
    const RenderSettings rs = test::smallSettings(40, 20, 4);
    RayStats st;
    const Image img = test::render(s, rs, &st, 2);
    EXPECT_TRUE(test::allFinite(img));
    // Count the samples whose primary ray meets either sphere: each of those is non-finite.
    const CameraRays cam(s.camera, rs.width, rs.height);
    uint64_t expect = 0;
    for (int y = 0; y < rs.height; ++y)
        for (int x = 0; x < rs.width; ++x)
            for (int k = 0; k < 4; ++k) {
                SampleRng rng(0, uint64_t(y) * rs.width + x, k);
                const float jx = rng.next(), jy = rng.next();
                Hit h;
                expect += s.geometry.intersect(cam.generate(x + ((k % 2) + jx) * 0.5f, y + ((k / 2) + jy) * 0.5f), h);
            }
    EXPECT_GT(expect, 100u);
    EXPECT_EQ(st.nonFinite, expect);
    const std::vector<uint8_t> rgb = toRgb8(img, ToneMap::Reinhard);
    EXPECT_EQ(rgb.size(), size_t(40 * 20 * 3));
}
