// KHR_materials_iridescence from glTF files (issue 43): the loader reads the factors and their
// defaults and refuses what the schema forbids (one line naming the material and the value);
// scenes/iridescence_spheres.gltf (tests/engine/materials/make_iridescence_spheres.py: four
// spheres under films of 100, 300, 400 and 600 nm) renders four distinct hues, and the same
// file with the extension taken out renders four grey spheres.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "engine/geometry/camera.h"
#include "engine/load/scene_loader.h"
#include "engine/util/errors.h"
#include "tests/engine/gltf_floor_scene.h"

using namespace rf;
using namespace gltftest;

namespace {

json filmMaterial(const json& film) {
    return {{"pbrMetallicRoughness", {{"baseColorFactor", {0.1, 0.1, 0.1, 1}}, {"metallicFactor", 0}}},
            {"extensions", {{"KHR_materials_iridescence", film}}}};
}

/// The hue (degrees) and saturation (max − min)/max of a linear colour.
struct Hue {
    double degrees, saturation;
};
Hue hueOf(const Color& c) {
    const double mx = maxComponent(c), mn = std::min({c.r, c.g, c.b}), d = mx - mn;
    double h = 0.0;
    if (d > 0.0) {
        if (mx == c.r) h = 60.0 * std::fmod((c.g - c.b) / d + 6.0, 6.0);
        else if (mx == c.g) h = 60.0 * ((c.b - c.r) / d + 2.0);
        else h = 60.0 * ((c.r - c.g) / d + 4.0);
    }
    return {h, mx > 0.0 ? d / mx : 0.0};
}
double hueDistance(double a, double b) {
    const double d = std::abs(a - b);
    return std::min(d, 360.0 - d);
}

/// Renders the spheres file (edited by `edit` first) under the built-in studio environment at
/// 240×90 and returns each sphere's mean linear colour over the pixels whose centre ray meets
/// it facing the camera (n·v above 0.8: near the normal incidence whose colours are known; the
/// rims' films are thinner along the ray and all turn alike); writes the picture to
/// RAYFARM_TEST_OUT/iridescence/NAME.png.
std::vector<Color> sphereColours(const std::string& name, const std::function<void(json&)>& edit) {
    const std::string src = std::string(RAYFARM_SOURCE_DIR) + "/scenes/iridescence_spheres.gltf";
    json doc = json::parse(readFile(src));
    if (edit) edit(doc);
    TempDir dir;
    writeFile(dir / "spheres.gltf", doc.dump());
    SceneOptions options;
    options.environment = EnvironmentSpec{"", 0.f, 1.f};
    DiskFileSource fs;
    LoadedScene loaded = loadScene(dir / "spheres.gltf", fs, options);
    Scene& scene = loaded.scene;
    useGltfCamera(scene, 0);
    RenderSettings s = scene.settings;
    s.width = 240;
    s.height = 90;
    s.toneMap = ToneMap::Clamp;
    s.exposure = 0.f;
    s.autoExposure = false;
    RayStats rays;
    const Image img = renderFrame(scene, {scene.camera, s}, 0, 0, rays);
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/iridescence";
    std::filesystem::create_directories(out);
    writePng(out + "/" + name + ".png", s.width, s.height, toRgb8(img, s));
    const CameraRays cam(scene.camera, s.width, s.height);
    std::vector<Color> sum(4, Color(0.f));
    std::vector<int> count(4, 0);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const Ray r = cam.generate(x + 0.5f, y + 0.5f);
            Hit hit;
            if (!scene.geometry.intersect(r, hit)) continue;
            const SurfaceInteraction si = scene.geometry.interaction(r, hit);
            if (glm::dot(si.ns, -r.d) < 0.8f) continue;
            const std::string& m = scene.materials[si.material].name;
            for (int k = 0; k < 4; ++k)
                if (m == doc["materials"][size_t(k)]["name"].get<std::string>()) {
                    const float* p = img.pixel(x, y);
                    sum[size_t(k)] += Color(p[0], p[1], p[2]);
                    ++count[size_t(k)];
                }
        }
    for (int k = 0; k < 4; ++k) {
        EXPECT_GT(count[size_t(k)], 100) << name << ": sphere " << k << " covers too few pixels";
        sum[size_t(k)] /= float(std::max(1, count[size_t(k)]));
    }
    return sum;
}

}  // namespace

TEST(GltfIridescence, ReadsTheFactorsAndTheirDefaults) {
    const Scene s = loadFloor(filmMaterial({{"iridescenceFactor", 0.8}}));
    const Material& m = s.materials[0];
    EXPECT_FLOAT_EQ(m.iridescence, 0.8f);
    EXPECT_FLOAT_EQ(m.iridescenceIor, 1.3f);
    EXPECT_FLOAT_EQ(m.iridescenceThicknessMin, 100.f);
    EXPECT_FLOAT_EQ(m.iridescenceThicknessMax, 400.f);
    EXPECT_EQ(m.iridescenceTexture, -1);
    for (const std::string& n : s.notes) EXPECT_EQ(n.find("iridescence"), std::string::npos) << n;

    const Scene t = loadFloor(filmMaterial({{"iridescenceFactor", 1},
                                            {"iridescenceIor", 1.8},
                                            {"iridescenceThicknessMinimum", 250},
                                            {"iridescenceThicknessMaximum", 700},
                                            {"iridescenceTexture", {{"index", 0}}},
                                            {"iridescenceThicknessTexture", {{"index", 1}}}}),
                              {{{255, 255, 255, 0, 0, 0}}, {{0, 0, 0, 0, 255, 0}}});
    const Material& n = t.materials[0];
    EXPECT_FLOAT_EQ(n.iridescenceIor, 1.8f);
    EXPECT_FLOAT_EQ(n.iridescenceThicknessMin, 250.f);
    EXPECT_FLOAT_EQ(n.iridescenceThicknessMax, 700.f);
    EXPECT_GE(n.iridescenceTexture, 0);
    EXPECT_GE(n.iridescenceThicknessTexture, 0);

    // Factor 0: no film, and its textures are never decoded.
    const Scene z = loadFloor(filmMaterial({{"iridescenceFactor", 0}, {"iridescenceTexture", {{"index", 0}}}}),
                              {{{255, 255, 255, 0, 0, 0}}});
    EXPECT_EQ(z.materials[0].iridescence, 0.f);
    EXPECT_EQ(z.materials[0].iridescenceTexture, -1);
}

TEST(GltfIridescence, RefusesWhatTheSchemaForbidsNamingTheMaterial) {
    auto refused = [](const json& film) {
        json m = filmMaterial(film);
        m["name"] = "Beetle";
        try {
            loadFloor(m);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string ior = refused({{"iridescenceFactor", 1}, {"iridescenceIor", 0.9}});
    EXPECT_NE(ior.find("materials[0] (\"Beetle\").extensions.KHR_materials_iridescence.iridescenceIor 0.9"), std::string::npos) << ior;
    const std::string thin = refused({{"iridescenceFactor", 1}, {"iridescenceThicknessMaximum", -5}});
    EXPECT_NE(thin.find("iridescenceThicknessMaximum -5: expected a thickness of 0 nm or more"), std::string::npos) << thin;
    EXPECT_EQ(thin.find('\n'), std::string::npos) << "one line: " << thin;
}

TEST(GltfIridescence, SpheresOfFourThicknessesShowFourHuesAndGreyWithoutTheFilm) {
    // Under a film of index 2.0 over dark grey, 100, 300, 400 and 600 nm reflect gold, blue,
    // magenta and green at normal incidence (thin_film.h per channel). Each sphere's mean colour
    // must be saturated and every two spheres' hues apart by at least kMinHueApart; without the
    // extension the same four spheres are grey (the studio environment's warm floor tints them a
    // little). Measured: hues 40, 235, 315 and 97 degrees (closest two 57 apart), saturation
    // 0.42 to 0.56; without the film saturation 0.029 to 0.043.
    constexpr double kMinSaturation = 0.25, kMinHueApart = 40.0, kGreySaturation = 0.08;
    const std::vector<Color> film = sphereColours("iridescence_spheres", nullptr);
    const std::vector<Color> grey = sphereColours("iridescence_spheres_stripped", [](json& d) {
        for (json& m : d["materials"]) m.erase("extensions");
        d.erase("extensionsUsed");
    });
    bool failed = false;
    for (size_t k = 0; k < 4; ++k) {
        const Hue h = hueOf(film[k]), g = hueOf(grey[k]);
        std::printf("sphere %zu: film (%.4f, %.4f, %.4f) hue %.0f saturation %.2f; without it (%.4f, %.4f, %.4f) saturation %.3f\n", k,
                    film[k].r, film[k].g, film[k].b, h.degrees, h.saturation, grey[k].r, grey[k].g, grey[k].b, g.saturation);
        if (h.saturation < kMinSaturation || g.saturation > kGreySaturation) failed = true;
        EXPECT_GE(h.saturation, kMinSaturation) << "sphere " << k;
        EXPECT_LE(g.saturation, kGreySaturation) << "sphere " << k << " without the film";
        for (size_t j = 0; j < k; ++j) {
            const double apart = hueDistance(h.degrees, hueOf(film[j]).degrees);
            EXPECT_GE(apart, kMinHueApart) << "spheres " << j << " and " << k;
            if (apart < kMinHueApart) failed = true;
        }
    }
    if (failed)
        ADD_FAILURE() << "pictures in " << RAYFARM_TEST_OUT << "/iridescence (iridescence_spheres.png, iridescence_spheres_stripped.png)";
}
