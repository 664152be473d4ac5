// The small scenes of tests/reference/ against their Blender Cycles references (rendered by
// tests/reference/cycles_reference.sh at 320×180; the commands are in the README there). Each is
// rendered as `rayfarm still SCENE --camera 0 --exposure EV --tonemap clamp [--environment ENV]`
// renders it (at its defaults otherwise: 4 spp, bounce light) and scored with SSIM and PSNR on
// the 8-bit images, over the rectangle the model's pixels span (the rows of black world above
// a floor are no test). Cycles path-traces (caustics, soft shadows from Blender's point and spot
// radius, glossy interreflection); the thresholds sit a little under what this renderer
// measured, and the images and error images are written on failure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "engine/geometry/camera.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "engine/util/image_metrics.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"

using namespace rf;

namespace {

const std::string kDir = std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/";

struct Expectation {
    double minSsim, minPsnr;
};

/// What a fair `rayfarm still --exposure 0 --tonemap clamp` at the reference's size renders with.
RenderSettings referenceSettings(const Scene& scene, int w, int h) {
    RenderSettings s = scene.settings;
    s.width = w;
    s.height = h;
    s.toneMap = ToneMap::Clamp;
    s.exposure = 0.f;
    s.autoExposure = false;
    return s;
}

/// The box of pixels whose centre ray first meets a mesh in the material named `material`
/// (any surface when `material` is empty).
struct PixelBox {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};
PixelBox materialPixels(const Scene& scene, int w, int h, const std::string& material) {
    const CameraRays rays(scene.camera, w, h);
    PixelBox b;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Ray r = rays.generate(x + 0.5f, y + 0.5f);
            Hit hit;
            if (!scene.geometry.intersect(r, hit)) continue;
            if (!material.empty()) {
                const SurfaceInteraction si = scene.geometry.interaction(r, hit);
                if (scene.materials[si.material].name != material) continue;
            }
            b.x0 = std::min(b.x0, x), b.y0 = std::min(b.y0, y), b.x1 = std::max(b.x1, x + 1), b.y1 = std::max(b.y1, y + 1);
        }
    return b;
}

std::vector<uint8_t> crop(const std::vector<uint8_t>& rgb, int w, const PixelBox& b) {
    std::vector<uint8_t> out;
    for (int y = b.y0; y < b.y1; ++y)
        out.insert(out.end(), rgb.begin() + (size_t(y) * w + b.x0) * 3, rgb.begin() + (size_t(y) * w + b.x1) * 3);
    return out;
}

/// material: score only the box of that material's pixels (empty: the whole model's).
ImageErrorMetrics scoreAgainstCycles(const std::string& name, const std::string& environment, Expectation want,
                                     float exposure = 0.f, const std::string& material = "") {
    SceneOptions options;
    if (!environment.empty())
        options.environment =
            EnvironmentSpec{std::string(RAYFARM_SOURCE_DIR) + "/scenes/environments/" + environment, 0.f, 1.f};
    DiskFileSource fs;
    LoadedScene sceneLoaded = loadScene(kDir + name + ".gltf", fs, options);
    Scene& scene = sceneLoaded.scene;
    useGltfCamera(scene, 0);
    int w = 0, h = 0;
    const std::vector<uint8_t> ref = readImageRgb8(kDir + name + ".cycles.png", w, h);
    RenderSettings s = referenceSettings(scene, w, h);
    s.exposure = exposure;
    RayStats rays;
    const std::vector<uint8_t> ours = toRgb8(renderFrame(scene, {scene.camera, s}, 0, 0, rays), s);
    const PixelBox box = materialPixels(scene, w, h, material);
    EXPECT_GT(box.width() * box.height(), w * h / 4) << name << ": the model covers a quarter of the picture at least";
    const ImageErrorMetrics e = compareRgb8(crop(ours, w, box), crop(ref, w, box), box.width(), box.height());
    std::printf("%s against Cycles (%dx%d of the model's pixels): SSIM %.4f, PSNR %.2f dB\n", name.c_str(), box.width(),
                box.height(), e.ssim, e.psnr);
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/cycles_scenes";
    std::filesystem::create_directories(out);
    writePng(out + "/" + name + ".png", w, h, ours);
    if (e.ssim < want.minSsim || e.psnr < want.minPsnr) {
        writePng(out + "/" + name + "_error.png", w, h, falseColorErrorRgb8(ours, ref, w, h, 0.25));
        ADD_FAILURE() << name << ": SSIM " << e.ssim << " (want >= " << want.minSsim << "), PSNR " << e.psnr
                      << " dB (want >= " << want.minPsnr << "); images in " << out;
    }
    return e;
}

}  // namespace

TEST(CyclesScenes, MetalsAndGlassUnderTheCourtyardMatchCycles) {
    // Measured 0.8820 / 21.25 dB on the model's pixels (0.8549 / 20.83 dB on the whole picture,
    // before bounce light). Most of the error: the rough copper box reflects a much darker
    // environment than in Cycles, and the floor is lighter.
    scoreAgainstCycles("metals_glass", "courtyard.exr", {0.87, 20.7});
}

TEST(CyclesScenes, BlendedPaneWithTextureAlphaMatchesCycles) {
    // tests/reference/make_blend_alpha.py: a pane of alphaMode BLEND, its alpha 0.25, 0.75 and 1
    // in thirds of its texture, before a ball and a box under the courtyard and a sun; scored on
    // the pane's pixels. Measured 0.9566 / 27.31 dB; before the texture's alpha counted (the pane
    // opaque blue) 0.8682 / 15.96 dB. Reference: 512 Cycles samples (tests/reference/README.md).
    scoreAgainstCycles("blend_alpha", "courtyard.exr", {0.94, 26.0}, 0.f, "blended pane");
}

TEST(CyclesScenes, TexturedBoxAndSpheresUnderASpotLightMatchCycles) {
    // Measured 0.9245 / 27.97 dB on the model's pixels (without bounce light 0.8852 / 23.76 dB;
    // 0.7572 / 22.17 dB on the whole picture at 1 spp when first written). Most of what is left:
    // the normal-mapped box, and the soft edges of Cycles' sized lights.
    scoreAgainstCycles("textured_spot", "", {0.91, 27.0});
}

// Blender exports (tests/reference/make_blender_scenes.py: Blender's own glTF exporter,
// double-sided materials, Blender's light units), each against Cycles at 1024 or 2048 samples.

TEST(CyclesScenes, BlenderShowcaseGlassBallOnAFloorUnderThreeLightsMatchesCycles) {
    // A clay monkey, a gold torus and a glass ball on a white floor under a point light, a spot
    // and a sun. Measured 0.9190 / 25.71 dB (without bounce light 0.8996 / 23.81 dB). Most of
    // the error: the ball's caustic and the soft shadows of Cycles' sized lights.
    scoreAgainstCycles("showcase", "", {0.90, 25.0});
}

TEST(CyclesScenes, BlenderBackdropPlaneUnderAnEnvironmentMatchesCycles) {
    // A grey double-sided backdrop seen from its back, a floor and a red ball, lit by the
    // courtyard alone. It came out near white (BD0) while the default key light of a model
    // without lights was added to the environment given for it. Measured 0.9524 / 26.04 dB.
    // Most of the error: the environment's light is unshadowed here (no contact shadow under
    // the ball, no darkening where backdrop meets floor).
    scoreAgainstCycles("backdrop", "courtyard.exr", {0.94, 25.5});
}

TEST(CyclesScenes, BlenderDimLightFileMatchesCyclesAtItsExposure) {
    // One point light of 10 cd (0.184 W in Blender) over a clay monkey and a box: at 10 EV both
    // renderers show it lit (pruning compares a light's worth after exposure). Measured
    // 0.8692 / 29.66 dB (without bounce light 0.8056 / 24.81 dB); the reference keeps some of
    // Cycles' noise at 2048 samples.
    scoreAgainstCycles("dim_light", "", {0.85, 29.0}, 10.f);
}

TEST(CyclesScenes, ClearcoatSheenAndVolumeMatchCyclesOnEachSphere) {
    // tests/reference/coat_sheen_volume.gltf: a red sphere under a clear coat, a blue velvet
    // sphere (sheen) and an amber glass sphere (transmission and volume attenuation), under the
    // courtyard and a sun. Scored on each sphere's own pixels (the box of the pixels its
    // material covers), so neither the floor nor the sky can hide a wrong material.
    SceneOptions options;
    std::string courtyard = RAYFARM_SOURCE_DIR;  // appended: GCC 12's operator+ warns falsely under LTO
    courtyard += "/scenes/environments/courtyard.exr";
    options.environment = EnvironmentSpec{courtyard, 0.f, 1.f};
    DiskFileSource fs;
    LoadedScene sceneLoaded = loadScene(kDir + "coat_sheen_volume.gltf", fs, options);
    Scene& scene = sceneLoaded.scene;
    useGltfCamera(scene, 0);
    for (const std::string& n : scene.notes)
        for (const char* ext : {"clearcoat", "sheen", "volume"}) EXPECT_EQ(n.find(ext), std::string::npos) << n;
    int w = 0, h = 0;
    const std::vector<uint8_t> ref = readImageRgb8(kDir + "coat_sheen_volume.cycles.png", w, h);
    const RenderSettings s = referenceSettings(scene, w, h);
    RayStats rays;
    const std::vector<uint8_t> ours = toRgb8(renderFrame(scene, {scene.camera, s}, 0, 0, rays), s);
    // The control: the same spheres without their coat, sheen and volume must score worse, and
    // below the thresholds, or the thresholds would not test the extensions.
    Scene plain = scene;
    for (Material& m : plain.materials) m.clearcoat = 0.f, m.sheenColor = Color(0.f), m.attenuation = Color(0.f);
    const std::vector<uint8_t> without = toRgb8(renderFrame(plain, {plain.camera, s}, 0, 0, rays), s);
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/cycles_scenes";
    std::filesystem::create_directories(out);
    writePng(out + "/coat_sheen_volume.png", w, h, ours);
    struct Sphere {
        const char* material;
        double minSsim, minPsnr;
    };
    // Measured 0.8995 / 21.08 dB, 0.8446 / 19.21 dB and 0.9175 / 22.10 dB (tests/reference/
    // README.md: what is left is mostly Cycles' bounce light, the velvet's Ashikhmin lobe against
    // Charlie, and the amber sphere's caustic on the floor beside it).
    const Sphere spheres[] = {{"red under clear coat", 0.88, 20.5},
                              {"blue velvet", 0.82, 18.7},
                              {"amber glass volume", 0.90, 21.5}};
    for (const Sphere& sp : spheres) {
        const PixelBox b = materialPixels(scene, w, h, sp.material);
        ASSERT_GT(b.width(), 20) << sp.material;
        ASSERT_GT(b.height(), 20) << sp.material;
        const std::vector<uint8_t> a = crop(ours, w, b), r = crop(ref, w, b);
        const ImageErrorMetrics e = compareRgb8(a, r, b.width(), b.height());
        const ImageErrorMetrics c = compareRgb8(crop(without, w, b), r, b.width(), b.height());
        std::printf("coat_sheen_volume %s against Cycles: SSIM %.4f, PSNR %.2f dB on %dx%d pixels (without the extension: %.4f, %.2f dB)\n",
                    sp.material, e.ssim, e.psnr, b.width(), b.height(), c.ssim, c.psnr);
        EXPECT_TRUE(c.ssim < sp.minSsim || c.psnr < sp.minPsnr) << sp.material << ": the control passes the thresholds too";
        if (e.ssim < sp.minSsim || e.psnr < sp.minPsnr) {
            std::string name = sp.material;
            for (char& c : name) c = c == ' ' ? '_' : c;
            writePng(out + "/coat_sheen_volume_" + name + "_error.png", b.width(), b.height(),
                     falseColorErrorRgb8(a, r, b.width(), b.height(), 0.25));
            ADD_FAILURE() << sp.material << ": SSIM " << e.ssim << " (want >= " << sp.minSsim << "), PSNR " << e.psnr
                          << " dB (want >= " << sp.minPsnr << "); images in " << out;
        }
    }
}

namespace {

/// One byte a pixel: 1 where the pixel's centre ray first meets a surface of `material`.
std::vector<uint8_t> materialMask(const Scene& scene, int w, int h, const std::string& material) {
    const CameraRays rays(scene.camera, w, h);
    std::vector<uint8_t> mask(size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Ray r = rays.generate(x + 0.5f, y + 0.5f);
            Hit hit;
            if (!scene.geometry.intersect(r, hit)) continue;
            const SurfaceInteraction si = scene.geometry.interaction(r, hit);
            mask[size_t(y) * w + x] = scene.materials[si.material].name == material;
        }
    return mask;
}

/// The mean 8-bit colour (as 0..1) of the pixels under mask.
Color maskedMean(const std::vector<uint8_t>& rgb, const std::vector<uint8_t>& mask) {
    double sum[3] = {0, 0, 0};
    size_t n = 0;
    for (size_t i = 0; i < mask.size(); ++i)
        if (mask[i]) {
            for (int c = 0; c < 3; ++c) sum[c] += rgb[3 * i + c];
            ++n;
        }
    return n ? Color(float(sum[0] / n / 255), float(sum[1] / n / 255), float(sum[2] / n / 255)) : Color(0.f);
}

}  // namespace

TEST(CyclesScenes, DefaultMaterialAndRoughMetalsMatchCyclesOnEachSphere) {
    // tests/reference/rough_metals.gltf under the courtyard: white metal at roughness 0, 0.25,
    // 0.5, 0.75 and 1 above glTF's default material (pbrMetallicRoughness: {}), gold, copper, a
    // metal with KHR_materials_transmission (opaque: the metal part does not transmit) and a
    // rough white plastic. The reference is Cycles' Multiscatter GGX (cycles_reference.sh
    // --multiscatter): Blender 3.4's default GGX scatters once and loses what rayfarm now gives
    // back under an environment (docs/pictures.md, Materials). Each sphere's pixels: masked SSIM >= 0.93 and the
    // mean colour within 3% per channel (issue 43). Not met yet (tests/reference/README.md has
    // the figures): it runs only under the shortfall label (ctest -L shortfall).
    if (!std::getenv("RAYFARM_SHORTFALL_RUN")) GTEST_SKIP() << "a known shortfall: runs under the shortfall label (ctest -L shortfall)";
    SceneOptions options;
    std::string courtyard = RAYFARM_SOURCE_DIR;
    courtyard += "/scenes/environments/courtyard.exr";
    options.environment = EnvironmentSpec{courtyard, 0.f, 1.f};
    DiskFileSource fs;
    Scene scene = loadScene(kDir + "rough_metals.gltf", fs, options).scene;
    useGltfCamera(scene, 0);
    int w = 0, h = 0;
    const std::vector<uint8_t> ref = readImageRgb8(kDir + "rough_metals.cycles.png", w, h);
    const RenderSettings s = referenceSettings(scene, w, h);
    RayStats rays;
    const std::vector<uint8_t> ours = toRgb8(renderFrame(scene, {scene.camera, s}, 0, 0, rays), s);
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/cycles_scenes";
    std::filesystem::create_directories(out);
    writePng(out + "/rough_metals.png", w, h, ours);
    const char* spheres[] = {"white metal r0.00", "white metal r0.25", "white metal r0.50", "white metal r0.75",
                             "white metal r1.00", "default material", "gold r0.5", "copper r0.8",
                             "metal with transmission", "white plastic r1"};
    bool failed = false;
    for (const char* material : spheres) {
        const std::vector<uint8_t> mask = materialMask(scene, w, h, material);
        ASSERT_GT(std::count(mask.begin(), mask.end(), uint8_t(1)), 600) << material;
        const double ssim = ssimRgb8Masked(ours, ref, w, h, mask);
        const Color a = maskedMean(ours, mask), b = maskedMean(ref, mask);
        std::printf("rough_metals %-24s SSIM %.4f, mean (%.3f, %.3f, %.3f) against Cycles (%.3f, %.3f, %.3f)\n", material,
                    ssim, a.r, a.g, a.b, b.r, b.g, b.b);
        EXPECT_GE(ssim, 0.93) << material;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 0.03f * b[c]) << material << " channel " << c;
        failed |= ssim < 0.93 || std::abs(a.r - b.r) > 0.03f * b.r || std::abs(a.g - b.g) > 0.03f * b.g ||
                  std::abs(a.b - b.b) > 0.03f * b.b;
    }
    if (failed) writePng(out + "/rough_metals_error.png", w, h, falseColorErrorRgb8(ours, ref, w, h, 0.25));
}
