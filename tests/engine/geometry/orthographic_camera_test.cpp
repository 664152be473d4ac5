// Orthographic cameras: parallel rays (an object's size in pixels does not depend on its
// distance), ymag/xmag as the view's half extents with the image's aspect, glTF's orthographic
// camera on Debian's Cameras.gltf, and the scene file's "type": "orthographic".
#include <gtest/gtest.h>

#include "tests/engine/engine_test_util.h"
#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {

const std::string kCameras = "/usr/share/assimp/models/glTF2/cameras/Cameras.gltf";

/// The box of pixels whose coverage is at least a half, and how many there are.
struct Covered {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1, count = 0;
};
Covered covered(const Image& img) {
    Covered c;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x)
            if (img.alpha()[size_t(y) * img.width() + x] >= 0.5f) {
                c.x0 = std::min(c.x0, x), c.y0 = std::min(c.y0, y);
                c.x1 = std::max(c.x1, x), c.y1 = std::max(c.y1, y);
                ++c.count;
            }
    return c;
}

/// A unit sphere at the origin seen along −z from distance `dist`, over a transparent background.
Image sphereAt(float dist, bool orthographic, int w, int h) {
    Scene s = test::emptyScene();
    s.geometry.spheres.push_back(Sphere{Vec3(0.f), 1.f, 0});
    s.transparentBackground = true;
    s.camera.eye = Vec3(0.f, 0.f, dist);
    s.camera.target = Vec3(0.f);
    s.camera.orthographic = orthographic;
    s.camera.orthoHalf = 2.f;  // the view is 4 units high
    s.camera.fovDeg = 40.f;
    s.build();
    return test::render(s, test::smallSettings(w, h));
}

Image renderCamera(const Scene& scene, int w, int h) {
    RenderSettings st = test::smallSettings(w, h);
    RayStats rays;
    return renderFrame(scene, {scene.camera, st}, 0, 1, rays);
}

LoadedScene loadJson(const std::string& text) {
    FileBundle b;
    b.files["o.json"] = text;
    BundleFileSource fs(b);
    return loadScene("o.json", fs);
}

std::string jsonError(const std::string& text) {
    try {
        loadJson(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(OrthographicCamera, RaysAreParallelAndLeaveTheImagePlane) {
    Camera c;
    c.eye = Vec3(1.f, 2.f, 10.f);
    c.target = Vec3(1.f, 2.f, 0.f);
    c.orthographic = true;
    c.orthoHalf = 3.f;
    const CameraRays rays(c, 200, 100);
    // The corners of a 200 × 100 image: ±3 high, ±6 wide (the image's aspect), all along −z.
    const Ray tl = rays.generate(0.f, 0.f), br = rays.generate(200.f, 100.f), mid = rays.generate(100.f, 50.f);
    for (const Ray& r : {tl, br, mid}) {
        EXPECT_EQ(r.d, Vec3(0.f, 0.f, -1.f));
        EXPECT_FLOAT_EQ(r.o.z, 10.f);
        EXPECT_FLOAT_EQ(r.coneSpread, 0.f);   // a pixel's footprint does not grow with distance
        EXPECT_FLOAT_EQ(r.coneWidth, 0.06f);  // 6 units over 100 rows
    }
    EXPECT_NEAR(tl.o.x, 1.f - 6.f, 1e-5f);
    EXPECT_NEAR(tl.o.y, 2.f + 3.f, 1e-5f);
    EXPECT_NEAR(br.o.x, 1.f + 6.f, 1e-5f);
    EXPECT_NEAR(br.o.y, 2.f - 3.f, 1e-5f);
    EXPECT_EQ(mid.o, Vec3(1.f, 2.f, 10.f));
    // The horizontal axis given instead: ±3 wide, ±1.5 high.
    c.fovHorizontal = true;
    const Ray h = CameraRays(c, 200, 100).generate(0.f, 0.f);
    EXPECT_NEAR(h.o.x, 1.f - 3.f, 1e-5f);
    EXPECT_NEAR(h.o.y, 2.f + 1.5f, 1e-5f);
}

TEST(OrthographicCamera, AnObjectsSizeInPixelsDoesNotDependOnItsDistance) {
    // A unit sphere in a view 4 units high at 64 × 64: a disc of radius 16 pixels, π·16² = 804
    // pixels, at any distance. The perspective camera's disc shrinks with distance (the test's
    // control: it can tell the two apart).
    const int expected = int(std::lround(kPi * 16.0 * 16.0));
    int counts[3];
    const float dists[3] = {3.f, 30.f, 3000.f};
    for (int i = 0; i < 3; ++i) {
        const Covered c = covered(sphereAt(dists[i], true, 64, 64));
        counts[i] = c.count;
        EXPECT_NEAR(c.count, expected, 0.02 * expected) << "distance " << dists[i];
        EXPECT_EQ(c.x0, 16) << dists[i];
        EXPECT_EQ(c.x1, 47) << dists[i];
        EXPECT_EQ(c.y0, 16) << dists[i];
        EXPECT_EQ(c.y1, 47) << dists[i];
    }
    EXPECT_LE(std::abs(counts[1] - counts[0]), 2);
    EXPECT_LE(std::abs(counts[2] - counts[0]), 2);
    const int near = covered(sphereAt(3.f, false, 64, 64)).count, far = covered(sphereAt(30.f, false, 64, 64)).count;
    EXPECT_GT(near, 4 * far);
}

TEST(OrthographicCamera, YmagIsTheHalfHeightAndTheWidthFollowsTheAspect) {
    // The same sphere in a 128 × 64 image: still 16 pixels in radius (square pixels), centred.
    const Covered c = covered(sphereAt(10.f, true, 128, 64));
    EXPECT_EQ(c.x0, 48);
    EXPECT_EQ(c.x1, 79);
    EXPECT_EQ(c.y0, 16);
    EXPECT_EQ(c.y1, 47);
}

TEST(OrthographicCamera, GltfOrthographicCameraOnDebiansCamerasFile) {
    DiskFileSource files;
    Scene scene = loadGltfScene(kCameras, files);
    // Both of the file's cameras, in node order: perspective (node 1), orthographic (node 2).
    ASSERT_EQ(scene.gltfCameras.size(), 2u);
    EXPECT_FALSE(scene.gltfCameras[0].orthographic);
    const Camera& o = scene.gltfCameras[1];
    EXPECT_TRUE(o.orthographic);
    EXPECT_FLOAT_EQ(o.orthoHalf, 1.f);  // ymag
    EXPECT_FALSE(o.fovHorizontal);
    const glm::dvec3 eye = glm::dvec3(o.eye) + scene.renderOrigin;
    EXPECT_NEAR(eye.x, 0.5, 1e-6);
    EXPECT_NEAR(eye.y, 0.5, 1e-6);
    EXPECT_NEAR(eye.z, 3.0, 1e-6);
    useGltfCamera(scene, 1);
    EXPECT_TRUE(scene.camera.orthographic);
    scene.transparentBackground = true;
    // At the file's aspect (xmag/ymag = 1): the view is x, y in [−0.5, 1.5] around the eye. The
    // square spans x in [0, 1]: columns 32..95 of 128. Its node turns it −45° about x, so its
    // far edge rises to y = cos 45° = 0.707: rows from (1.5 − 0.707)/2·128 = 50.7 to 96.
    const Covered c = covered(renderCamera(scene, 128, 128));
    EXPECT_EQ(c.x0, 32);
    EXPECT_EQ(c.x1, 95);
    EXPECT_EQ(c.y0, 51);
    EXPECT_EQ(c.y1, 95);
    // At twice the width the view keeps ymag: the square keeps its 64 columns, centred.
    const Covered wide = covered(renderCamera(scene, 256, 128));
    EXPECT_EQ(wide.x0, 96);
    EXPECT_EQ(wide.x1, 159);
    EXPECT_EQ(wide.y0, 51);
    EXPECT_EQ(wide.y1, 95);
    // The perspective camera at the same place sees the square smaller than half the width
    // (yfov 0.7 rad spans 2·3·tan 0.35 = 2.19 units at the square's base, more than 2).
    useGltfCamera(scene, 0);
    const Covered p = covered(renderCamera(scene, 128, 128));
    EXPECT_LT(p.x1 - p.x0 + 1, 64);
}

TEST(OrthographicCamera, SceneFileKeys) {
    const LoadedScene sLoaded = loadJson(R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], "type": "orthographic", "ymag": 2.5},
                                 "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})");
    const Scene& s = sLoaded.scene;
    EXPECT_TRUE(s.camera.orthographic);
    EXPECT_FLOAT_EQ(s.camera.orthoHalf, 2.5f);
    EXPECT_FALSE(s.camera.fovHorizontal);
    const LoadedScene xLoaded = loadJson(R"({"camera": {"type": "orthographic", "xmag": 3}, "objects": []})");
    const Scene& x = xLoaded.scene;
    EXPECT_TRUE(x.camera.orthographic);
    EXPECT_FLOAT_EQ(x.camera.orthoHalf, 3.f);
    EXPECT_TRUE(x.camera.fovHorizontal);
    EXPECT_FALSE(loadJson(R"({"camera": {"fov": 30}, "objects": []})").scene.camera.orthographic);

    EXPECT_EQ(jsonError(R"({"camera": {"type": "fisheye"}})"), "o.json: camera.type: expected \"perspective\" or \"orthographic\"");
    EXPECT_EQ(jsonError(R"({"camera": {"type": "orthographic"}})"),
              "o.json: camera: an orthographic camera needs one of xmag (half width) or ymag (half height), in scene units");
    EXPECT_EQ(jsonError(R"({"camera": {"type": "orthographic", "xmag": 1, "ymag": 1}})"),
              "o.json: camera: an orthographic camera needs one of xmag (half width) or ymag (half height), in scene units");
    EXPECT_EQ(jsonError(R"({"camera": {"type": "orthographic", "ymag": 0}})"),
              "o.json: camera.ymag: expected a positive half extent in scene units");
    EXPECT_EQ(jsonError(R"({"camera": {"type": "orthographic", "ymag": 1, "fov": 40}})"),
              "o.json: camera.fov: an orthographic camera has no field of view; give xmag or ymag");
    EXPECT_EQ(jsonError(R"({"camera": {"ymag": 1}})"),
              "o.json: camera.ymag: only an orthographic camera (\"type\": \"orthographic\") has one");
}

TEST(OrthographicCamera, SceneFileCameraRendersTheSameSizeAtAnyDistance) {
    auto coverOf = [](double z) {
        LoadedScene sLoaded = loadJson(R"({"camera": {"eye": [0, 0, )" + std::to_string(z) +
                           R"(], "target": [0, 0, 0], "type": "orthographic", "ymag": 2},
                               "background": "transparent",
                               "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})");
        Scene& s = sLoaded.scene;
        return covered(test::render(s, test::smallSettings(64, 64))).count;
    };
    EXPECT_LE(std::abs(coverOf(4.0) - coverOf(400.0)), 2);
    EXPECT_NEAR(coverOf(4.0), kPi * 256.0, 0.02 * kPi * 256.0);
}
