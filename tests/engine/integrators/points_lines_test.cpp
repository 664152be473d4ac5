// glTF points and lines as pictures: the glTF Asset Generator's unit square outlined with
// LINES (Mesh_PrimitiveMode_08, indexed), framed by default in a 640×360 picture. The outline
// (framed here by the loader's bounding-sphere camera, a little wider than the turntable's fit)
// is drawn about --point-size pixels wide (1.5 by default) and shows in the rendered picture
// against the background beside it; a larger size draws it wider.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/geometry/camera.h"
#include "engine/integrators/render.h"
#include "engine/load/gltf/gltf_loader.h"

using namespace rf;

namespace {

const std::string kFile = "/usr/share/assimp/models/glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf";
constexpr int kW = 640, kH = 360;

Scene outline(float pointSize) {
    SceneOptions o;
    o.assets.pointSize = pointSize;
    DiskFileSource fs;
    return loadGltfScene(kFile, fs, o);
}

/// Which pixels' centre rays meet the outline.
std::vector<uint8_t> hitMask(const Scene& s) {
    const CameraRays rays(s.camera, kW, kH);
    std::vector<uint8_t> hit(size_t(kW) * kH, 0);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            Hit h;
            hit[size_t(y) * kW + x] = s.geometry.intersect(rays.generate(x + 0.5f, y + 0.5f), h);
        }
    return hit;
}

/// The median length of the runs of hit pixels along the rows of the picture's middle third
/// (where the outline's two upright sides cross them).
int medianRowRun(const std::vector<uint8_t>& hit) {
    std::vector<int> runs;
    for (int y = kH / 3; y < 2 * kH / 3; ++y)
        for (int x = 0, run = 0; x <= kW; ++x) {
            if (x < kW && hit[size_t(y) * kW + x]) ++run;
            else if (run) runs.push_back(run), run = 0;
        }
    if (runs.empty()) return 0;
    std::nth_element(runs.begin(), runs.begin() + ptrdiff_t(runs.size() / 2), runs.end());
    return runs[runs.size() / 2];
}

}  // namespace

TEST(PointsAndLines, TheOutlineIsAboutOneAndAHalfPixelsWideAndShows) {
    Scene s = outline(1.5f);
    s.settings.width = kW;
    s.settings.height = kH;
    const std::vector<uint8_t> hit = hitMask(s);
    const int run = medianRowRun(hit);
    std::printf("outline at --point-size 1.5: median %d pixels across\n", run);
    EXPECT_GE(run, 1);
    EXPECT_LE(run, 2) << "the lines should read as 1–2 pixels at the default framing";
    // The picture: where the outline is, it differs from the background a few pixels beside it.
    RayStats rays;
    const Image img = renderFrame(s, {s.camera, s.settings}, 0, 0, rays);
    double contrast = 0.0;
    int n = 0;
    for (int y = kH / 3; y < 2 * kH / 3; ++y)
        for (int x = 4; x < kW - 4; ++x) {
            if (!hit[size_t(y) * kW + x] || hit[size_t(y) * kW + x - 4]) continue;
            const float* p = img.data() + (size_t(y) * kW + x) * 3;
            const float* q = img.data() + (size_t(y) * kW + x - 4) * 3;
            contrast += std::abs((p[0] + p[1] + p[2]) - (q[0] + q[1] + q[2])) / 3.0;
            ++n;
        }
    ASSERT_GT(n, 100) << "too few outline pixels in the middle rows";
    EXPECT_GT(contrast / n, 0.1) << "the outline does not show against the background";
}

TEST(PointsAndLines, PointSizeWidensTheOutline) {
    const int thin = medianRowRun(hitMask(outline(1.5f)));
    const int wide = medianRowRun(hitMask(outline(8.f)));
    EXPECT_GE(wide, 4);
    EXPECT_GE(wide, 3 * thin);
}

TEST(PointsAndLines, BlenderLoosePointsKeepTheirVertexColours) {
    // tests/reference/make_points_lines.py: Blender's exporter wrote a ring of 24 loose vertices
    // as POINTS with COLOR_0 running from red (Blender x = −1.6) to blue (x = +1.6), beside a
    // cube and a helix of loose edges (LINES).
    DiskFileSource fs;
    const Scene s = loadGltfScene(std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/points_lines.glb", fs, SceneOptions{});
    auto colourAt = [&](float x) {
        Ray r;  // straight down onto the ring's point at (x, 0, 0) (glTF's y is Blender's z)
        r.o = Vec3(x, 0.5f, 0.f) - Vec3(s.renderOrigin);
        r.d = Vec3(0.f, -1.f, 0.f);
        Hit h;
        EXPECT_TRUE(s.geometry.intersect(r, h)) << "no dot at x = " << x;
        return s.geometry.interaction(r, h).color;
    };
    const Vec4 blue = colourAt(1.6f), red = colourAt(-1.6f);
    EXPECT_NEAR(blue.r, 0.f, 0.02f);
    EXPECT_NEAR(blue.b, 1.f, 0.02f);
    EXPECT_NEAR(red.r, 1.f, 0.02f);
    EXPECT_NEAR(red.b, 0.f, 0.02f);
    // The helix's 60 segments and the ring's 24 points, beside the cube's 12 triangles.
    size_t triangles = 0;
    for (const TriangleMesh& m : s.geometry.meshes) triangles += m.triangleCount();
    EXPECT_EQ(triangles, 12u + 24u * 8 + 61u * 8 + 60u * 12);
}
