// The glTF loader on real files from Debian's assimp-testmodels: the 2CylinderEngine, the
// BoxTextured container variants, cameras, texture transforms, an unknown extension and a
// morph-target animation. Expectations come from the files' JSON, read here independently.
#include <gtest/gtest.h>

#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/integrators/render.h"

using namespace rf;
using namespace gltftest;

namespace {

const std::string kGltf2 = "/usr/share/assimp/models/glTF2/";

/// The JSON of a .gltf or .glb file.
json gltfJson(const std::string& path) {
    const std::string bytes = readFile(path);
    if (bytes.compare(0, 4, "glTF") == 0) {
        uint32_t len;
        std::memcpy(&len, bytes.data() + 12, 4);
        return json::parse(bytes.substr(20, len));
    }
    return json::parse(bytes);
}

glm::dmat4 nodeLocal(const json& n) {
    if (n.contains("matrix")) {
        std::vector<double> m = n["matrix"].get<std::vector<double>>();
        return glm::make_mat4(m.data());
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (n.contains("translation")) t = glm::translate(t, glm::dvec3(n["translation"][0], n["translation"][1], n["translation"][2]));
    if (n.contains("rotation")) r = glm::mat4_cast(glm::dquat(n["rotation"][3], n["rotation"][0], n["rotation"][1], n["rotation"][2]));
    if (n.contains("scale")) s = glm::scale(s, glm::dvec3(n["scale"][0], n["scale"][1], n["scale"][2]));
    return t * r * s;
}

/// Visits (node, worldFromNode) over the default scene.
template <typename F>
void walk(const json& g, F&& f) {
    std::function<void(int, glm::dmat4)> rec = [&](int i, glm::dmat4 parent) {
        const glm::dmat4 m = parent * nodeLocal(g["nodes"][i]);
        f(g["nodes"][i], m);
        if (g["nodes"][i].contains("children"))
            for (int c : g["nodes"][i]["children"]) rec(c, m);
    };
    for (int r : g["scenes"][g.value("scene", 0)]["nodes"]) rec(r, glm::dmat4(1.0));
}

Image render(const Scene& scene, const Camera& cam, int w, int h) {
    RenderSettings s = scene.settings;
    s.width = w;
    s.height = h;
    RayStats stats;
    return renderFrame(scene, {cam, s}, 0, 1, stats);
}

bool allFinite(const Image& img) {
    for (int i = 0; i < img.width() * img.height() * 3; ++i)
        if (!std::isfinite(img.data()[i])) return false;
    return true;
}

bool isBackground(const Image& img, int x, int y, const Color& bg) {
    const float* p = img.pixel(x, y);
    return p[0] == bg.r && p[1] == bg.g && p[2] == bg.b;
}

bool hasNote(const Scene& s, const std::string& text) {
    for (const std::string& n : s.notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST(GltfLoader, EngineLoadsEveryTriangleWithinItsNodeBounds) {
    const std::string path = kGltf2 + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    const json g = gltfJson(path);
    size_t expected = 0;
    glm::dvec3 lo(1e300), hi(-1e300);
    walk(g, [&](const json& node, const glm::dmat4& m) {
        if (!node.contains("mesh")) return;
        for (const json& p : g["meshes"][int(node["mesh"])]["primitives"]) {
            if (p.value("mode", 4) != 4) continue;
            expected += size_t(g["accessors"][int(p["indices"])]["count"]) / 3;
            const json& acc = g["accessors"][int(p["attributes"]["POSITION"])];
            for (int k = 0; k < 8; ++k) {
                const glm::dvec3 c(acc["min"][0].get<double>() * !(k & 1) + acc["max"][0].get<double>() * !!(k & 1),
                                   acc["min"][1].get<double>() * !(k & 2) + acc["max"][1].get<double>() * !!(k & 2),
                                   acc["min"][2].get<double>() * !(k & 4) + acc["max"][2].get<double>() * !!(k & 4));
                const glm::dvec3 w(m * glm::dvec4(c, 1.0));
                lo = glm::min(lo, w);
                hi = glm::max(hi, w);
            }
        }
    });
    // Triangles with a repeated index, counted per drawn instance from the binary chunk.
    const std::string bytes = readFile(path);
    uint32_t jsonLen;
    std::memcpy(&jsonLen, bytes.data() + 12, 4);
    const size_t bin = 20 + jsonLen + 8;
    size_t repeated = 0;
    walk(g, [&](const json& node, const glm::dmat4&) {
        if (!node.contains("mesh")) return;
        for (const json& p : g["meshes"][int(node["mesh"])]["primitives"]) {
            const json& acc = g["accessors"][int(p["indices"])];
            const json& view = g["bufferViews"][int(acc["bufferView"])];
            const size_t at = bin + view.value("byteOffset", size_t(0)) + acc.value("byteOffset", size_t(0));
            const int size = acc["componentType"] == 5125 ? 4 : 2;
            auto index = [&](size_t i) {
                uint32_t v = 0;
                std::memcpy(&v, bytes.data() + at + i * size, size);
                return v;
            };
            for (size_t t = 0; t + 2 < size_t(acc["count"]); t += 3)
                repeated += index(t) == index(t + 1) || index(t + 1) == index(t + 2) || index(t) == index(t + 2);
        }
    });
    DiskFileSource files;
    Scene scene = loadGltfScene(path, files);
    size_t dropped = 0;
    for (const std::string& n : scene.notes)
        if (n.find("degenerate triangles dropped") != std::string::npos) dropped = std::stoul(n.substr(n.rfind(": ") + 2));
    std::printf("2CylinderEngine: %zu triangles loaded of %zu in the file; %zu dropped (%zu with a repeated index)\n",
                scene.geometry.triangleCount(), expected, dropped, repeated);
    EXPECT_GT(expected, 100000u);
    EXPECT_EQ(scene.geometry.triangleCount() + dropped, expected);
    EXPECT_GE(dropped, repeated);
    EXPECT_LE(dropped, repeated + expected / 1000);  // beyond repeated indices, only a few zero-area ones
    const Aabb b = scene.geometry.bounds();
    const glm::dvec3 blo = glm::dvec3(b.lo) + scene.renderOrigin, bhi = glm::dvec3(b.hi) + scene.renderOrigin;
    const double size = glm::length(hi - lo);
    for (int a = 0; a < 3; ++a) {
        // The loaded bounds lie inside the union of the transformed accessor boxes and fill
        // most of it (the union is loose only where parts are rotated).
        EXPECT_GE(blo[a], lo[a] - 1e-5 * size) << a;
        EXPECT_LE(bhi[a], hi[a] + 1e-5 * size) << a;
        EXPECT_GE(bhi[a] - blo[a], 0.8 * (hi[a] - lo[a])) << a;
    }
    // Render space is rebased near the model's centre, so coordinates stay small.
    EXPECT_LT(glm::length(glm::dvec3(b.lo + b.hi) * 0.5), 64.0 * 1.8);
    EXPECT_TRUE(scene.textures.empty());
    EXPECT_EQ(scene.lights.size(), 1u) << "the default key light, beside the built-in studio";
    ASSERT_TRUE(scene.environment) << "a bare model stands in the built-in studio";
    EXPECT_TRUE(scene.environmentBackground);

    // The default camera frames the whole model: it covers a good part of the image but
    // never touches the border. Misses show the plain background here, to tell them apart.
    scene.environmentBackground = false;
    const Image img = render(scene, scene.camera, 160, 90);
    ASSERT_TRUE(allFinite(img));
    int border = 0, x0 = 160, x1 = -1;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 160; ++x) {
            const bool bg = isBackground(img, x, y, scene.background);
            if (!bg) x0 = std::min(x0, x), x1 = std::max(x1, x);
            if (!bg && (x == 0 || y == 0 || x == 159 || y == 89)) ++border;
        }
    EXPECT_EQ(border, 0);
    // The bounding sphere fills 1/1.15 of the image height; the engine, seen from 30° off its
    // long axis, spans well over half of that across.
    EXPECT_GT(x1 - x0, 90 / 2);
    fs::create_directories(RAYFARM_TEST_OUT);
    writePng(std::string(RAYFARM_TEST_OUT) + "/gltf_engine.png", 160, 90, toRgb8(img, ToneMap::Clamp));
}

TEST(GltfLoader, BoxTexturedVariantsGiveTheSameImage) {
    // Debian's separate-files variant samples with MIRRORED_REPEAT/CLAMP where the others
    // REPEAT (its UVs run to u = 6), so it is compared after setting its sampler to theirs.
    TempDir dir;
    const std::string sep = kGltf2 + "BoxTextured-glTF/";
    json g = gltfJson(sep + "BoxTextured.gltf");
    ASSERT_EQ(g["samplers"][0]["wrapS"], 33648);
    g["samplers"][0]["wrapS"] = 10497;
    g["samplers"][0]["wrapT"] = 10497;
    writeFile(dir / "BoxTextured.gltf", g.dump());
    writeFile(dir / "BoxTextured0.bin", readFile(sep + "BoxTextured0.bin"));
    writeFile(dir / "CesiumLogoFlat.png", readFile(sep + "CesiumLogoFlat.png"));
    const std::vector<std::string> variants = {kGltf2 + "BoxTextured-glTF-Binary/BoxTextured.glb",
                                               kGltf2 + "BoxTextured-glTF-Embedded/BoxTextured.gltf", dir / "BoxTextured.gltf",
                                               sep + "BoxTextured.gltf"};
    std::vector<Image> images;
    for (const std::string& v : variants) {
        DiskFileSource files;
        const Scene scene = loadGltfScene(v, files);
        EXPECT_EQ(scene.geometry.triangleCount(), 12u) << v;
        ASSERT_EQ(scene.textures.size(), 1u) << v;
        images.push_back(render(scene, scene.camera, 96, 72));
        ASSERT_TRUE(allFinite(images.back()));
    }
    auto differing = [&](size_t k) {
        int n = 0;
        for (int i = 0; i < 96 * 72 * 3; ++i) n += images[k].data()[i] != images[0].data()[i];
        return n;
    };
    // Textured, not flat: many distinct values on the box.
    std::set<float> distinct(images[0].data(), images[0].data() + 96 * 72 * 3);
    EXPECT_GT(distinct.size(), 50u);
    EXPECT_EQ(differing(1), 0) << "embedded differs from binary";
    EXPECT_EQ(differing(2), 0) << "separate files differ from binary";
    EXPECT_GT(differing(3), 100) << "mirrored wrapping must change the faces where u > 1";
    writePng(std::string(RAYFARM_TEST_OUT) + "/gltf_boxtextured.png", 96, 72, toRgb8(images[0], ToneMap::Clamp));
}

TEST(GltfLoader, PerspectiveCamerasAreStoredAndSelectable) {
    const std::string path = kGltf2 + "cameras/Cameras.gltf";
    DiskFileSource files;
    Scene scene = loadGltfScene(path, files);
    ASSERT_EQ(scene.gltfCameras.size(), 2u);  // and the orthographic one (orthographic_camera_test.cpp)
    EXPECT_FALSE(hasNote(scene, "skipped"));
    const Camera& c = scene.gltfCameras[0];
    // Node 1: translation (0.5, 0.5, 3), no rotation: looks down −z with +y up.
    const glm::dvec3 eye = glm::dvec3(c.eye) + scene.renderOrigin;
    EXPECT_NEAR(eye.x, 0.5, 1e-6);
    EXPECT_NEAR(eye.y, 0.5, 1e-6);
    EXPECT_NEAR(eye.z, 3.0, 1e-6);
    const Vec3 fwd = glm::normalize(c.target - c.eye);
    EXPECT_NEAR(fwd.z, -1.f, 1e-6f);
    EXPECT_NEAR(c.up.y, 1.f, 1e-6f);
    EXPECT_NEAR(c.fovDeg, 0.7 * 180.0 / 3.14159265358979, 1e-4);
    useGltfCamera(scene, 0);
    EXPECT_EQ(scene.camera.eye, c.eye);
    EXPECT_THROW(useGltfCamera(scene, 2), InputError);
    // The square (x, y in [0, 1], tilted 45° about x) sits straight ahead of the camera
    // (misses show the plain background, not the built-in studio, to tell them apart).
    scene.environmentBackground = false;
    const Image img = render(scene, scene.camera, 64, 64);
    EXPECT_FALSE(isBackground(img, 32, 32, scene.background));
    EXPECT_TRUE(isBackground(img, 0, 0, scene.background));
}

TEST(GltfLoader, TextureTransformsAreReadFromTheSampleModel) {
    const std::string path = kGltf2 + "textureTransform/TextureTransformTest.gltf";
    const json g = gltfJson(path);
    DiskFileSource files;
    const Scene scene = loadGltfScene(path, files);
    int checked = 0;
    for (const json& gm : g["materials"]) {
        const json& info = gm["pbrMetallicRoughness"]["baseColorTexture"];
        if (!info.contains("extensions")) continue;
        const json& t = info["extensions"]["KHR_texture_transform"];
        for (const Material& m : scene.materials) {
            if (m.name != gm["name"]) continue;
            ++checked;
            ASSERT_GE(m.baseColorTexture, 0) << m.name;
            EXPECT_FLOAT_EQ(m.baseColorTransform.rotation, t.value("rotation", 0.f)) << m.name;
            EXPECT_FLOAT_EQ(m.baseColorTransform.offset.x, t.contains("offset") ? float(t["offset"][0]) : 0.f) << m.name;
            EXPECT_FLOAT_EQ(m.baseColorTransform.offset.y, t.contains("offset") ? float(t["offset"][1]) : 0.f) << m.name;
            EXPECT_FLOAT_EQ(m.baseColorTransform.scale.x, t.contains("scale") ? float(t["scale"][0]) : 1.f) << m.name;
        }
    }
    EXPECT_EQ(checked, 6);
    // Two images (UV grid, arrow) are used by the quads; the marker images are too.
    EXPECT_GE(scene.textures.size(), 2u);
}

TEST(TextureTransform, RotationTurnsUvsCounterClockwiseInVDownSpace) {
    // KHR_texture_transform rotates UVs counter-clockwise as seen on the UV map, whose v axis
    // points down (glTF issue #1563; the TextureTransformTest sample model's green marker):
    // u' = cos·u + sin·v, v' = −sin·u + cos·v. A quarter turn takes (1, 0) to (0, −1).
    TextureTransform t;
    t.rotation = kPi / 2;
    const Vec2 r = applyTextureTransform(t, Vec2(1.f, 0.f));
    EXPECT_NEAR(r.x, 0.f, 1e-6f);
    EXPECT_NEAR(r.y, -1.f, 1e-6f);
    // Order is T·R·S: scale (2, 3) first, then rotate, then offset.
    t.scale = Vec2(2.f, 3.f);
    t.offset = Vec2(0.5f, 0.25f);
    const Vec2 q = applyTextureTransform(t, Vec2(1.f, 1.f));
    EXPECT_NEAR(q.x, 0.5f + 3.f, 1e-5f);
    EXPECT_NEAR(q.y, 0.25f - 2.f, 1e-5f);
}

TEST(GltfLoader, ClearCoatLoadsAndItsExtensionIsNotNoted) {
    DiskFileSource files;
    const Scene scene = loadGltfScene(kGltf2 + "ClearCoat-glTF/ClearCoatTest.gltf", files);
    EXPECT_GT(scene.geometry.triangleCount(), 0u);
    EXPECT_FALSE(hasNote(scene, "KHR_materials_clearcoat"));  // supported since issue 29
    const Image img = render(scene, scene.camera, 64, 36);
    EXPECT_TRUE(allFinite(img));
}

TEST(GltfLoader, MorphCubeKeepsItsAnimationAndMovesWithWeights) {
    const std::string path = kGltf2 + "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
    const json g = gltfJson(path);
    DiskFileSource files;
    Scene scene = loadGltfScene(path, files);
    ASSERT_EQ(scene.geometry.models.size(), 1u);
    const SceneGraph& model = scene.geometry.models[0];
    ASSERT_EQ(model.animations.size(), 1u);
    const Animation& a = model.animations[0];
    ASSERT_EQ(a.channels.size(), 1u);
    EXPECT_EQ(a.channels[0].path, AnimPath::Weights);
    EXPECT_EQ(a.channels[0].node, 0);
    const AnimSampler& s = a.samplers[0];
    const size_t keys = g["accessors"][int(g["animations"][0]["samplers"][0]["input"])]["count"];
    EXPECT_EQ(s.times.size(), keys);
    EXPECT_EQ(s.components, 2);  // two morph targets
    EXPECT_EQ(s.values.size(), keys * 2);
    EXPECT_NEAR(a.duration(), g["accessors"][int(g["animations"][0]["samplers"][0]["input"])]["max"][0].get<double>(), 1e-6);

    ASSERT_EQ(scene.geometry.meshes.size(), 1u);
    const TriangleMesh before = scene.geometry.meshes[0];
    EXPECT_EQ(before.node, 0);
    EXPECT_EQ(before.model, 0);
    ASSERT_EQ(before.morphPositions.size(), 2u);
    // Weight 1 on target 0 moves every vertex by its delta, through the node's transform.
    const glm::dmat4 renderFromNode = model.renderFromModel * nodeLocal(g["nodes"][0]);
    scene.geometry.applyNodeTransforms(0, {renderFromNode}, {{1.0, 0.0}});
    double maxMove = 0.0;
    for (size_t i = 0; i < before.objectPositions.size(); ++i) {
        const glm::dvec3 want(renderFromNode * glm::dvec4(glm::dvec3(before.objectPositions[i] + before.morphPositions[0][i]), 1.0));
        EXPECT_NEAR(glm::length(glm::dvec3(scene.geometry.meshes[0].positions[i]) - want), 0.0, 1e-4) << i;
        maxMove =
            std::max(maxMove, glm::length(glm::dvec3(scene.geometry.meshes[0].positions[i] - before.positions[i])));
    }
    EXPECT_GT(maxMove, 1.0);  // the target visibly moves the cube (scaled by 100)
}

TEST(GltfLoader, UnusedTexturesAreNotDecoded) {
    // A copy of BoxTextured whose image is garbage: decoding it would leave a note. Without a
    // material that uses it, nothing is decoded and nothing is said.
    TempDir dir;
    const std::string src = kGltf2 + "BoxTextured-glTF/";
    json g = gltfJson(src + "BoxTextured.gltf");
    writeFile(dir / "BoxTextured0.bin", readFile(src + "BoxTextured0.bin"));
    writeFile(dir / "CesiumLogoFlat.png", "this is not a PNG");
    writeFile(dir / "used.gltf", g.dump());
    g["materials"][0]["pbrMetallicRoughness"].erase("baseColorTexture");
    writeFile(dir / "unused.gltf", g.dump());
    DiskFileSource files;
    const Scene unused = loadGltfScene(dir / "unused.gltf", files);
    EXPECT_TRUE(unused.textures.empty());
    EXPECT_FALSE(hasNote(unused, "decod"));
    const Scene used = loadGltfScene(dir / "used.gltf", files);
    EXPECT_TRUE(used.textures.empty());
    EXPECT_TRUE(hasNote(used, "not decodable")) << "the used texture was tried and its failure said";
}

TEST(GltfLoader, Gltf1IsRefusedWithAMessageSayingSo) {
    DiskFileSource files;
    for (const char* p : {"glTF/BoxTextured-glTF/BoxTextured.gltf", "glTF/BoxTextured-glTF-Binary/BoxTextured.glb"}) {
        try {
            loadGltfScene(std::string("/usr/share/assimp/models/") + p, files);
            ADD_FAILURE() << p << " loaded";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("glTF 1.0"), std::string::npos) << e.what();
        }
    }
}
