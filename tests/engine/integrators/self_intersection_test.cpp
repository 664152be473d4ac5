// Rays spawned from a surface never meet that surface again (catalogue #11 on triangles): flat
// quads stay one uniform value wherever they lie, and Debian's assimp files whose flat quads
// came out speckled render as smooth as their geometry allows.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "farm/report/stability/stability_cases.h"
#include "engine/geometry/triangle.h"

using namespace rf;

namespace {

/// Share of a static file's surface pixels that change by more than 2 levels (8-bit, any
/// channel) between two frames differing only in their sample jitter (seeded by the frame
/// index). Surface pixels: covered (alpha 1) with their whole 5×5 neighbourhood, so silhouettes
/// do not count. A speckle-free render changes only where an edge inside the surface (a
/// texture's, a real shadow's) falls differently into a pixel's strata; self-shadowed samples
/// change pixels everywhere on it.
constexpr double kSpeckleShare = 0.02;  // the bound AssimpFlatQuadsAreNotSpeckled holds

/// against: Jitter compares two sample sets; NoShadows compares one with the same frame rendered
/// without shadow rays (for textured files, whose texture edges change with the jitter: what
/// self-shadowing adds there, beside the few real shadows a file casts on itself).
enum class Against { Jitter, NoShadows };

double jitterSpeckle(const std::string& path, int width, int height, Against against) {
    DiskFileSource files;
    Scene scene = loadGltfScene(path, files);
    scene.transparentBackground = true;
    RenderSettings s = scene.settings;
    s.width = width;
    s.height = height;
    s.spp = 4;
    s.autoExposure = false;
    s.exposure = 0.f;
    RayStats rays;
    const Image fa = renderFrame(scene, {scene.camera, s}, 0, 2, rays);
    if (against == Against::NoShadows)
        for (Light& l : scene.lights) l.castShadows = false;
    const Image fb = renderFrame(scene, {scene.camera, s}, against == Against::Jitter ? 1 : 0, 2, rays);
    const std::vector<uint8_t> a = toRgb8(fa, s), b = toRgb8(fb, s);
    int surface = 0, changed = 0;
    std::vector<uint8_t> diff(a.size(), 0);  // white where a surface pixel changed, grey elsewhere on it
    for (int y = 2; y < height - 2; ++y)
        for (int x = 2; x < width - 2; ++x) {
            bool inside = true;
            for (int dy = -2; dy <= 2 && inside; ++dy)
                for (int dx = -2; dx <= 2; ++dx) inside &= fa.alpha()[size_t((y + dy) * width + x + dx)] >= 1.f;
            if (!inside) continue;
            ++surface;
            const size_t i = 3 * (size_t(y) * width + x);
            bool differs = false;
            for (int c = 0; c < 3; ++c) differs |= std::abs(int(a[i + c]) - int(b[i + c])) > 2;
            changed += differs;
            for (int c = 0; c < 3; ++c) diff[i + c] = differs ? 255 : 64;
        }
    const std::string stem = std::string(RAYFARM_TEST_OUT) + "/speckle_" + std::filesystem::path(path).stem().string();
    if (double(changed) > kSpeckleShare * surface) {
        std::filesystem::create_directories(RAYFARM_TEST_OUT);
        writePng(stem + ".png", width, height, a);
        writePng(stem + "_changed.png", width, height, diff);
    }
    EXPECT_GT(surface, width * height / 10) << path << ": too little surface to measure";
    return surface ? double(changed) / surface : 1.0;
}

}  // namespace

// The uniformly lit quad of stability::flatQuads (two triangles filling the frame, a grazing
// light among two) near the origin, far from it and tilted: every pixel keeps the lit value.
// The bound is this test's own: a standard deviation of 0.5 levels over 48×48 pixels at 4 spp.
TEST(SelfIntersection, FlatQuadIsUniformAtEveryOffsetAndTilt) {
    for (float z : {1e-3f, 0.3f, 1e3f, 1e5f})
        for (float tilt : {0.f, 10.f, 30.f, 60.f, 89.f}) {
            const double sd = stability::flatQuadSpeckle(z, tilt, 2);
            EXPECT_LE(sd, 0.5) << "quad at z = " << z << ", tilted " << tilt << "°";
        }
}

// A ray leaving a triangle from a point offset by the point's error bound, in any direction
// above the surface, does not report the triangle (or its coplanar neighbour) at t ≈ 0. The
// quad lies at z = 1e-3 with vertices ~1 from the origin: the point's own z error (~1e-10) is far
// below the error of a t computed from coordinates of size 1, so the offset alone cannot do it.
TEST(SelfIntersection, RayFromTheSurfaceDoesNotHitItsOwnTriangles) {
    const Vec3 p0(-1.f, -1.f, 1e-3f), p1(1.f, -1.f, 1e-3f), p2(1.f, 1.f, 1e-3f), p3(-1.f, 1.f, 1e-3f);
    int selfHits = 0, rays = 0;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            // Points along the diagonal and everywhere else, through the first triangle.
            const float b1 = (i + 0.5f) / 64.f, b2 = (j + 0.5f) / 64.f * (1.f - b1);
            TriangleHit h;
            h.b0 = 1.f - b1 - b2;
            h.b1 = b1;
            h.b2 = b2;
            Vec3 err;
            const Vec3 p = triangleHitPoint(p0, p1, p2, h, err);
            const float a = 0.05f + 1.5f * float(i * 64 + j) / 4096.f;  // up to 86° off the normal
            const Vec3 d = glm::normalize(Vec3(std::cos(7.f * a) * std::sin(a), std::sin(7.f * a) * std::sin(a), std::cos(a)));
            Ray r;
            r.o = offsetRayOrigin(p, err, Vec3(0, 0, 1), d);
            r.d = d;
            const WatertightRay wr(r);
            TriangleHit t;
            selfHits += intersectTriangleWatertight(wr, p0, p1, p2, kInf, t);
            selfHits += intersectTriangleWatertight(wr, p0, p2, p3, kInf, t);
            ++rays;
        }
    EXPECT_EQ(selfHits, 0) << "of " << rays << " rays";
}

// The triangle test's own error bound only drops hits that cannot be told from t = 0: a
// triangle 1e-3 above the origin of a ray of direction +z is still hit at t = 1e-3.
TEST(SelfIntersection, NearHitsBeyondTheErrorBoundStay) {
    Ray r;
    r.o = Vec3(0.f);
    r.d = Vec3(0, 0, 1);
    TriangleHit h;
    ASSERT_TRUE(intersectTriangleWatertight(WatertightRay(r), Vec3(-1, -1, 1e-3f), Vec3(1, -1, 1e-3f), Vec3(0, 1, 1e-3f), kInf, h));
    EXPECT_NEAR(h.t, 1e-3f, 1e-9f);
    r.o = Vec3(1e3f, 0.f, 0.f);  // far from the origin: a gap of 1e-3 is still 16 ulps
    ASSERT_TRUE(intersectTriangleWatertight(WatertightRay(r), Vec3(999, -1, 1e-3f), Vec3(1001, -1, 1e-3f), Vec3(1000, 1, 1e-3f), kInf, h));
    EXPECT_NEAR(h.t, 1e-3f, 1e-7f);
}

// Debian's assimp files with flat quads that rendered speckled (each pixel one of five values at
// 4 spp, a dark band along the diagonal), at the default look (studio environment, default light
// rig, 4 spp, 320×240): at most 2% of the surface's pixels change by more than 2 levels between
// two sample sets (untextured quads) or against the same frame without shadow rays (textured
// ones; texcoord_crash's quads cast real shadows on the plane behind them, 4.3% of its surface,
// so it is held to 6%). Measured before the triangle test bounded its own t error: 65% to 84%;
// after: 0% on the plain quads, 0.46% and 4.26% on the textured files.
TEST(SelfIntersection, AssimpFlatQuadsAreNotSpeckled) {
    const std::string root = "/usr/share/assimp/models/glTF2/";
    struct File {
        std::string path;
        Against against;
        double bound;
    };
    std::vector<File> files;
    for (const char* n : {"04", "05", "06", "11", "12", "13", "14", "15"})
        files.push_back({root + "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_" + n + ".gltf", Against::Jitter, kSpeckleShare});
    files.push_back({root + "textureTransform/TextureTransformTest.gltf", Against::NoShadows, kSpeckleShare});
    files.push_back({root + "issue_3269/texcoord_crash.gltf", Against::NoShadows, 0.06});
    for (const File& f : files) {
        const double share = jitterSpeckle(f.path, 320, 240, f.against);
        EXPECT_LE(share, f.bound) << f.path;
        std::printf("%s: %.2f%% of surface pixels changed\n", f.path.c_str(), 100.0 * share);
    }
}
