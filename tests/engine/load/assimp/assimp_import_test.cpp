// Models that are not glTF, read through assimp into the glTF model the glTF loader takes:
// small files written here whose expected materials, axes and colours are worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/util/errors.h"
#include "engine/util/file_source.h"
#include "engine/util/image.h"
#include "engine/load/gltf/gltf_images.h"
#include "engine/load/assimp/assimp_import.h"
#include "engine/load/model_inspect.h"
#include "engine/load/scene_loader.h"
#include "engine/integrators/render.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
using gltftest::TempDir;
using gltftest::writeFile;

namespace {

tinygltf::Model import(const std::string& path, std::vector<std::string>* notesOut = nullptr) {
    DiskFileSource fs;
    std::vector<std::string> notes;
    tinygltf::Model m = importAssimpModel(path, fs, {}, notes);
    if (notesOut) *notesOut = notes;
    return m;
}

/// A tetrahedron-free unit cube's 12 triangles as OBJ faces over 8 corners.
const char* kCubeFaces =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 4/4 3/3 2/2\nf 5/1 6/2 7/3 8/4\nf 1/1 2/2 6/3 5/4\nf 4/1 8/4 7/3 3/2\nf 1/1 5/2 8/3 4/4\nf 2/1 3/2 7/3 6/4\n";

/// Mean of the picture's pixels (linear), to tell a drawn model from an empty frame.
double meanOfFrame(const std::string& path) {
    DiskFileSource fs;
    SceneOptions opts;
    opts.width = 64;
    opts.height = 36;
    LoadedScene loaded = loadScene(path, fs, opts);
    RenderSettings s = loaded.scene.settings;
    s.spp = 1;
    RayStats stats;
    const Image img = renderFrame(loaded.scene, {loaded.scene.camera, s}, 0, 1, stats);
    double sum = 0;
    for (int i = 0; i < img.width() * img.height() * 3; ++i) sum += img.data()[i];
    return sum / (img.width() * img.height() * 3);
}

}  // namespace

TEST(AssimpImport, ObjMaterialMapsOntoTheGltfBrdf) {
    TempDir dir;
    writeFile(dir / "cube.obj", std::string("mtllib cube.mtl\nusemtl red\n") + kCubeFaces);
    // Kd the base colour, Ns 250 → roughness 1 − √(250/1000) = 0.5, d 0.25 → blended alpha,
    // Ks 0.25 → specularColorFactor 0.5 (F0 0.02), Ke 2 0 0 → emissive (1, 0, 0) × strength 2.
    writeFile(dir / "cube.mtl",
              "newmtl red\nKd 0.8 0.1 0.2\nKs 0.25 0.25 0.25\nNs 250\nd 0.25\nKe 2 0 0\nmap_Kd tex.png\n");
    writeFile(dir / "tex.png", gltftest::readFile(std::string(RAYFARM_SOURCE_DIR) + "/examples/contact-box-after.png"));
    const tinygltf::Model m = import(dir / "cube.obj");
    ASSERT_EQ(m.materials.size(), 2u);  // assimp's default material, then the file's
    const tinygltf::Material* red = nullptr;
    for (const auto& mat : m.materials)
        if (mat.name == "red") red = &mat;
    ASSERT_TRUE(red);
    const auto& pbr = red->pbrMetallicRoughness;
    EXPECT_NEAR(pbr.baseColorFactor[0], 0.8, 1e-6);
    EXPECT_NEAR(pbr.baseColorFactor[1], 0.1, 1e-6);
    EXPECT_NEAR(pbr.baseColorFactor[2], 0.2, 1e-6);
    EXPECT_NEAR(pbr.baseColorFactor[3], 0.25, 1e-6);
    EXPECT_EQ(red->alphaMode, "BLEND");
    EXPECT_NEAR(pbr.roughnessFactor, 0.5, 1e-6);
    EXPECT_EQ(pbr.metallicFactor, 0.0);
    ASSERT_TRUE(red->extensions.count("KHR_materials_specular"));
    EXPECT_NEAR(red->extensions.at("KHR_materials_specular").Get("specularColorFactor").Get(0).GetNumberAsDouble(), 0.5, 1e-6);
    ASSERT_EQ(red->emissiveFactor.size(), 3u);
    EXPECT_NEAR(red->emissiveFactor[0], 1.0, 1e-6);
    EXPECT_NEAR(red->extensions.at("KHR_materials_emissive_strength").Get("emissiveStrength").GetNumberAsDouble(), 2.0, 1e-6);
    ASSERT_GE(pbr.baseColorTexture.index, 0);
    const tinygltf::Image& img = m.images[size_t(m.textures[size_t(pbr.baseColorTexture.index)].source)];
    EXPECT_EQ(img.uri, "tex.png");
    EXPECT_GT(img.image.size(), 1000u);  // the PNG's bytes, kept encoded
    // OBJ is Y up in metres: the root is left as it is.
    EXPECT_TRUE(m.nodes[0].matrix.empty());
}

// MTL's Ks 0 (spider.obj's, and many older files'): no specular reflection at all, as Blender's
// Specular 0 renders it. specularColorFactor 0 alone would keep glTF's Fresnel rim (F90 is
// specularFactor), which lit the dark rough spider to a mean colour of 0.276 0.214 0.169 where
// Cycles shows 0.222 0.163 0.109 (0.238 0.171 0.112 without the rim;
// AssimpCycles.ObjWithMtlTexturesMatchesBlendersImport). Ks above 0 keeps specularFactor 1.
TEST(AssimpImport, ObjBlackKsMeansNoSpecular) {
    TempDir dir;
    writeFile(dir / "cube.obj", std::string("mtllib cube.mtl\nusemtl matte\nusemtl shiny\n") + kCubeFaces);
    writeFile(dir / "cube.mtl", "newmtl matte\nKd 0.2 0.2 0.2\nKs 0 0 0\nNs 0\nnewmtl shiny\nKd 0.2 0.2 0.2\nKs 0.01 0 0\n");
    const tinygltf::Model m = import(dir / "cube.obj");
    int seen = 0;
    for (const auto& mat : m.materials) {
        if (mat.name != "matte" && mat.name != "shiny") continue;
        ++seen;
        ASSERT_TRUE(mat.extensions.count("KHR_materials_specular")) << mat.name;
        const tinygltf::Value& spec = mat.extensions.at("KHR_materials_specular");
        EXPECT_NEAR(spec.Get("specularColorFactor").Get(0).GetNumberAsDouble(), mat.name == "matte" ? 0.0 : 0.02, 1e-6) << mat.name;
        if (mat.name == "matte") {
            ASSERT_TRUE(spec.Has("specularFactor"));
            EXPECT_EQ(spec.Get("specularFactor").GetNumberAsDouble(), 0.0);
        } else {
            EXPECT_FALSE(spec.Has("specularFactor"));  // glTF's default, 1
        }
    }
    EXPECT_EQ(seen, 2);
}

TEST(AssimpImport, ObjPbrExtensionRoughnessMetallic) {
    TempDir dir;
    writeFile(dir / "cube.obj", std::string("mtllib cube.mtl\nusemtl metal\n") + kCubeFaces);
    writeFile(dir / "cube.mtl", "newmtl metal\nKd 0.9 0.9 0.9\nPr 0.3\nPm 1\n");
    const tinygltf::Model m = import(dir / "cube.obj");
    bool found = false;
    for (const auto& mat : m.materials)
        if (mat.name == "metal") {
            found = true;
            EXPECT_NEAR(mat.pbrMetallicRoughness.roughnessFactor, 0.3, 1e-6);
            EXPECT_NEAR(mat.pbrMetallicRoughness.metallicFactor, 1.0, 1e-6);
        }
    EXPECT_TRUE(found);
}

// Maps the formats keep apart and glTF in one texture (assimp_textures.h): MTL's map_d becomes
// the base colour texture's alpha, map_Pr and map_Pm glTF's metallicRoughness texture (G, B),
// each at the larger map's size.
TEST(AssimpImport, SeparateOpacityMetalnessAndRoughnessMapsAreCombined) {
    TempDir dir;
    auto grey = [](int side, uint8_t v, uint8_t r = 0, uint8_t g = 0, uint8_t b = 0, bool colour = false) {
        std::vector<uint8_t> px(size_t(side) * side * 3, v);
        if (colour)
            for (size_t i = 0; i < px.size(); i += 3) px[i] = r, px[i + 1] = g, px[i + 2] = b;
        return encodePng(side, side, px, 3);
    };
    writeFile(dir / "base.png", grey(4, 0, 200, 30, 10, true));
    writeFile(dir / "opacity.png", grey(2, 64));
    writeFile(dir / "rough.png", grey(4, 51));
    writeFile(dir / "metal.png", grey(2, 255));
    writeFile(dir / "cube.obj", std::string("mtllib cube.mtl\nusemtl m\n") + kCubeFaces);
    writeFile(dir / "cube.mtl", "newmtl m\nKd 1 1 1\nmap_Kd base.png\nmap_d opacity.png\nmap_Pr rough.png\nmap_Pm metal.png\n");
    std::vector<std::string> notes;
    const tinygltf::Model m = import(dir / "cube.obj", &notes);
    const tinygltf::Material* mat = nullptr;
    for (const auto& x : m.materials)
        if (x.name == "m") mat = &x;
    ASSERT_TRUE(mat);
    auto decoded = [&](int texture) {
        EXPECT_GE(texture, 0);
        const auto& img = m.images.at(size_t(m.textures.at(size_t(texture)).source));
        std::string why;
        auto out = gltf::decodeImage(img.image.data(), img.image.size(), 0, why);
        EXPECT_TRUE(out) << why;
        return out.value_or(gltf::Rgba8Image{});
    };
    const gltf::Rgba8Image base = decoded(mat->pbrMetallicRoughness.baseColorTexture.index);
    ASSERT_EQ(base.width, 4);
    for (size_t i = 0; i < base.pixels.size(); i += 4) {
        EXPECT_EQ(base.pixels[i], 200);
        EXPECT_EQ(base.pixels[i + 1], 30);
        EXPECT_EQ(base.pixels[i + 2], 10);
        EXPECT_EQ(base.pixels[i + 3], 64);
    }
    EXPECT_EQ(mat->alphaMode, "BLEND");
    const gltf::Rgba8Image mr = decoded(mat->pbrMetallicRoughness.metallicRoughnessTexture.index);
    ASSERT_EQ(mr.width, 4);
    for (size_t i = 0; i < mr.pixels.size(); i += 4) {
        EXPECT_EQ(mr.pixels[i + 1], 51);   // roughness
        EXPECT_EQ(mr.pixels[i + 2], 255);  // metalness
    }
    EXPECT_EQ(mat->pbrMetallicRoughness.metallicFactor, 1.0);
    EXPECT_EQ(mat->pbrMetallicRoughness.roughnessFactor, 1.0);
    for (const std::string& n : notes) EXPECT_EQ(n.find("ignored (glTF takes alpha"), std::string::npos) << n;

    // A roughness map alone on a metal (Pm 0.7): B stays 1, so the factor alone sets metalness.
    writeFile(dir / "metal.obj", std::string("mtllib metal.mtl\nusemtl r\n") + kCubeFaces);
    writeFile(dir / "metal.mtl", "newmtl r\nKd 1 1 1\nPm 0.7\nmap_Pr rough.png\n");
    const tinygltf::Model m2 = import(dir / "metal.obj");
    for (const auto& x : m2.materials)
        if (x.name == "r") {
            EXPECT_NEAR(x.pbrMetallicRoughness.metallicFactor, 0.7, 1e-6);
            const int t = x.pbrMetallicRoughness.metallicRoughnessTexture.index;
            ASSERT_GE(t, 0);
            const auto& img = m2.images.at(size_t(m2.textures.at(size_t(t)).source));
            std::string why;
            const auto px = gltf::decodeImage(img.image.data(), img.image.size(), 0, why);
            ASSERT_TRUE(px) << why;
            EXPECT_EQ(px->pixels[1], 51);
            EXPECT_EQ(px->pixels[2], 255);
        }
}

TEST(AssimpImport, StlIsZUpMillimetresAndNeutral) {
    TempDir dir;
    // A triangle standing 10 mm tall along +Z: after the turn to Y up it must stand along +Y,
    // a hundredth of a metre.
    writeFile(dir / "t.stl",
              "solid t\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 0 10\nendloop\nendfacet\nendsolid t\n");
    const tinygltf::Model m = import(dir / "t.stl");
    const auto& r = m.nodes[0].matrix;
    ASSERT_EQ(r.size(), 16u);
    // Column-major: model +Z (column 2) goes to +Y (row 1) × 0.001.
    EXPECT_NEAR(r[2 * 4 + 1], 0.001, 1e-12);
    EXPECT_NEAR(r[1 * 4 + 2], -0.001, 1e-12);
    EXPECT_NEAR(r[0], 0.001, 1e-12);
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0].name, "default");
    EXPECT_NEAR(m.materials[0].pbrMetallicRoughness.baseColorFactor[0], 0.8, 1e-9);
    DiskFileSource fs;
    const GltfInfo info = inspectModel(dir / "t.stl", fs);
    EXPECT_EQ(info.format, "STL");
    EXPECT_EQ(info.drawnTriangles, 1u);
    ASSERT_EQ(info.meshes.size(), 1u);
    EXPECT_NEAR(info.meshes[0].max.z, 10.0, 1e-6);  // mesh space, as the file writes it
}

TEST(AssimpImport, PlyVertexColoursBecomeLinear) {
    TempDir dir;
    writeFile(dir / "c.ply",
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n"
              "0 0 0 255 0 0\n1 0 0 0 128 0\n0 1 0 0 0 255\n3 0 1 2\n");
    const tinygltf::Model m = import(dir / "c.ply");
    ASSERT_EQ(m.meshes.size(), 1u);
    const tinygltf::Primitive& p = m.meshes[0].primitives[0];
    ASSERT_TRUE(p.attributes.count("COLOR_0"));
    const tinygltf::Accessor& a = m.accessors[size_t(p.attributes.at("COLOR_0"))];
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    const float* c = reinterpret_cast<const float*>(m.buffers[0].data.data() + v.byteOffset);
    // Vertex order may change; find the green one: 128/255 in sRGB is 0.2158605 linear.
    bool green = false;
    for (size_t i = 0; i < a.count; ++i)
        if (c[4 * i + 1] > 0.f) {
            green = true;
            EXPECT_NEAR(c[4 * i + 1], 0.2158605f, 1e-4f);
        }
    EXPECT_TRUE(green);
    EXPECT_EQ(m.materials[size_t(p.material)].name, "vertex colours");
    EXPECT_EQ(m.materials[size_t(p.material)].pbrMetallicRoughness.baseColorFactor[0], 1.0);
}

TEST(AssimpImport, TexturesOutsideTheAssetRootAreRefused) {
    TempDir dir;
    writeFile(dir / "inside/cube.obj", std::string("mtllib cube.mtl\nusemtl m\n") + kCubeFaces);
    writeFile(dir / "inside/cube.mtl", "newmtl m\nKd 1 1 1\nmap_Kd ../outside.png\n");
    writeFile(dir / "outside.png", "not read");
    DiskFileSource fs;
    std::vector<std::string> notes;
    AssetOptions assets;
    assets.root = dir / "inside";
    try {
        importAssimpModel(dir / "inside/cube.obj", fs, assets, notes);
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("outside the asset root"), std::string::npos) << what;
        EXPECT_EQ(what.rfind(dir / "inside/cube.obj", 0), 0u) << what;
    }
    // An MTL outside the root is never opened either.
    writeFile(dir / "inside/b.obj", std::string("mtllib ../evil.mtl\nusemtl m\n") + kCubeFaces);
    writeFile(dir / "evil.mtl", "newmtl m\nKd 1 0 0\n");
    EXPECT_THROW(importAssimpModel(dir / "inside/b.obj", fs, assets, notes), InputError);
    EXPECT_EQ(fs.bundle().files.count(dir / "evil.mtl"), 0u);
}

TEST(AssimpImport, MalformedFilesAreOneLineRefusals) {
    TempDir dir;
    writeFile(dir / "bad.stl", std::string("\x00\x01garbage", 9));
    writeFile(dir / "bad.fbx", "Kaydara FBX Binary  \x00\x1a\x00 truncated");
    writeFile(dir / "bad.dae", "<?xml version=\"1.0\"?><COLLADA><library_geometries><geometry>");
    writeFile(dir / "empty.obj", "");
    for (const char* name : {"bad.stl", "bad.fbx", "bad.dae", "empty.obj"}) {
        DiskFileSource fs;
        try {
            loadScene(dir / name, fs);
            ADD_FAILURE() << name << ": loaded";
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(dir / name, 0), 0u) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
}

TEST(AssimpImport, CountsNoFileOfItsSizeCanHoldAreRefusedBeforeAssimpReadsThem) {
    TempDir dir;
    writeFile(dir / "big.ply",
              "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n");
    writeFile(dir / "big.dae", "<?xml version=\"1.0\"?><COLLADA><library_geometries><geometry><mesh><source>"
                               "<float_array id=\"a\" count=\"900000000\">0 0 0</float_array></source></mesh></geometry>"
                               "</library_geometries></COLLADA>");
    for (const char* name : {"big.ply", "big.dae"}) {
        DiskFileSource fs;
        std::vector<std::string> notes;
        try {
            importAssimpModel(dir / name, fs, {}, notes);
            ADD_FAILURE() << name << ": imported";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("bytes can hold"), std::string::npos) << e.what();
        }
    }
}

TEST(AssimpImport, ModelsRenderAndWorkersLoadTheSameFromTheBundle) {
    const std::string obj = "/usr/share/assimp/models/OBJ/spider.obj";
    EXPECT_GT(meanOfFrame(obj), 0.01);
    // The farm's workers load from the bundle rank 0 read: it must hold the MTL and textures
    // too, and give the same scene.
    DiskFileSource disk;
    std::vector<std::string> notes;
    const tinygltf::Model a = importAssimpModel(obj, disk, {}, notes);
    EXPECT_TRUE(disk.bundle().files.count("/usr/share/assimp/models/OBJ/spider.mtl"));
    BundleFileSource bundle(disk.bundle());
    const tinygltf::Model b = importAssimpModel(obj, bundle, {}, notes);
    EXPECT_EQ(a.buffers[0].data, b.buffers[0].data);
    ASSERT_EQ(a.images.size(), b.images.size());
    EXPECT_GE(a.images.size(), 1u);
    for (size_t i = 0; i < a.images.size(); ++i) EXPECT_EQ(a.images[i].image, b.images[i].image);
}

TEST(AssimpImport, SceneFileModelsMayBeObjOrStl) {
    TempDir dir;
    writeFile(dir / "cube.obj", std::string("mtllib cube.mtl\nusemtl red\n") + kCubeFaces);
    writeFile(dir / "cube.mtl", "newmtl red\nKd 0.8 0.1 0.1\n");
    writeFile(dir / "t.stl",
              "solid t\nfacet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1000 0 0\nvertex 0 0 1000\nendloop\nendfacet\nendsolid t\n");
    writeFile(dir / "scene.json", R"({"camera": {"eye": [0.5, 0.5, 4], "target": [0.5, 0.5, 0]},
        "lights": [{"position": [2, 3, 4]}],
        "objects": [{"type": "model", "path": "cube.obj"},
                    {"type": "model", "path": "t.stl", "transform": {"translate": [3, 0, 0]}}]})");
    DiskFileSource fs;
    const LoadedScene loaded = loadScene(dir / "scene.json", fs);
    // The cube's red material, and the STL's triangle turned upright in metres: 1000 mm along
    // +Z becomes 1 m along +Y, at x = 3.
    bool red = false;
    for (const Material& m : loaded.scene.materials) red = red || (m.gltfPbr && std::abs(m.color.r - 0.8f) < 1e-6f && std::abs(m.color.g - 0.1f) < 1e-6f);
    EXPECT_TRUE(red);
    Hit hit;
    Ray ray;
    ray.o = Vec3(DVec3(3.2, 0.5, 2.0) - loaded.scene.renderOrigin);
    ray.d = Vec3(0.f, 0.f, -1.f);
    EXPECT_TRUE(loaded.scene.geometry.intersect(ray, hit)) << "the STL's triangle does not stand up";
    ray.o = Vec3(DVec3(3.2, 0.0, 0.5) - loaded.scene.renderOrigin) + Vec3(0.f, 2.f, 0.f);
    ray.d = Vec3(0.f, -1.f, 0.f);
    EXPECT_FALSE(loaded.scene.geometry.intersect(ray, hit)) << "the STL's triangle lies flat";
}
