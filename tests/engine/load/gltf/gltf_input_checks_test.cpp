// Issue 14 #1, #7, #9: glTF input that used to crash the loader or fall back silently. Each
// case either refuses the file (InputError naming it) or leaves a note saying what was done.
#include <gtest/gtest.h>

#include <array>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/load/scene_loader.h"

using namespace rf;
using namespace gltftest;

namespace {

float kA[3] = {0, 0, 0}, kB[3] = {1, 0, 0}, kC[3] = {0, 1, 0};

/// Loads `doc` (written as model.gltf with the triangle buffer beside it); returns the error
/// message, or "" and the scene.
std::string load(const json& doc, Scene& scene, const std::string& text = "") {
    TempDir dir;
    writeFile(dir / "tri.bin", oneTriangleBytes(kA, kB, kC));
    writeFile(dir / "model.gltf", text.empty() ? doc.dump() : text);
    DiskFileSource files;
    try {
        loadGltfModel(scene, dir / "model.gltf", DMat4(1.0), files);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

int notesWith(const Scene& s, const std::string& needle) {
    int n = 0;
    for (const std::string& note : s.notes) n += note.find(needle) != std::string::npos;
    return n;
}

json withBounds(json doc, std::vector<double> lo, std::vector<double> hi) {
    doc["accessors"][0]["min"] = lo;
    doc["accessors"][0]["max"] = hi;
    return doc;
}

}  // namespace

TEST(GltfInputChecks, DeeplyNestedExtrasAreRefusedNotACrash) {
    // 20,000 levels overflowed the stack inside tinygltf's recursive JSON walk (SIGSEGV).
    json doc = oneTriangleGltf("tri.bin");
    std::string text = doc.dump();
    text.insert(1, "\"extras\": " + std::string(20000, '[') + std::string(20000, ']') + ",");
    Scene s;
    const std::string e = load(doc, s, text);
    EXPECT_NE(e.find("JSON nests more than 128 levels deep"), std::string::npos) << e;
}

TEST(GltfInputChecks, DeeplyNestedGlbJsonChunkIsRefused) {
    TempDir dir;
    std::string js = "{\"asset\":{\"version\":\"2.0\"},\"extras\":";
    for (int i = 0; i < 20000; ++i) js += "{\"a\":";
    js += "1" + std::string(20000, '}') + "}";
    while (js.size() % 4) js += ' ';
    std::string glb = "glTF";
    put<uint32_t>(glb, {2u, uint32_t(20 + js.size()), uint32_t(js.size()), 0x4E4F534Au});
    glb += js;
    writeFile(dir / "deep.glb", glb);
    DiskFileSource files;
    Scene s;
    try {
        loadGltfModel(s, dir / "deep.glb", DMat4(1.0), files);
        ADD_FAILURE() << "deep GLB loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("JSON nests more than"), std::string::npos) << e.what();
    }
}

TEST(GltfInputChecks, VertexOutsideDeclaredBoundsIsDroppedAndNoted) {
    // A flipped exponent bit put a vertex at -1.7e38: the default camera framed that and the
    // picture was background only, with no note.
    float far[3] = {-1.7e38f, 0, 0};
    TempDir dir;
    std::string buf = oneTriangleBytes(kA, kB, kC) + oneTriangleBytes(kA, far, kC);
    writeFile(dir / "two.bin", buf);
    json doc = withBounds(oneTriangleGltf("two.bin"), {0, 0, 0}, {1, 1, 0});
    doc["accessors"][0]["count"] = 6;
    doc["bufferViews"][0]["byteLength"] = 72;
    doc["buffers"][0]["byteLength"] = 72;
    writeFile(dir / "m.gltf", doc.dump());
    DiskFileSource files;
    Scene s;
    loadGltfModel(s, dir / "m.gltf", DMat4(1.0), files);
    EXPECT_EQ(notesWith(s, "1 vertices lie outside POSITION's declared min/max"), 1);
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    EXPECT_EQ(s.geometry.meshes[0].indices.size(), 3u);  // the good triangle only
    for (const Vec3& p : s.geometry.meshes[0].positions) EXPECT_LT(std::abs(p.x), 10.f);
}

TEST(GltfInputChecks, ModelEntirelyOutsideItsBoundsIsRefused) {
    // As a bare model (rayfarm render model.gltf): nothing is left to frame and draw.
    TempDir dir;
    writeFile(dir / "tri.bin", oneTriangleBytes(kA, kB, kC));
    writeFile(dir / "model.gltf", withBounds(oneTriangleGltf("tri.bin"), {5, 5, 5}, {6, 6, 6}).dump());
    DiskFileSource files;
    try {
        loadScene(dir / "model.gltf", files);
        ADD_FAILURE() << "a model with every vertex outside its bounds loaded";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("3 vertices lie outside POSITION's declared min/max"), std::string::npos) << e.what();
    }
}

TEST(GltfInputChecks, BoundsThatHoldGiveNoBoundsNote) {
    Scene s;
    EXPECT_EQ(load(withBounds(oneTriangleGltf("tri.bin"), {0, 0, 0}, {1, 1, 0}), s), "");
    EXPECT_EQ(notesWith(s, "min/max"), 0);
    Scene t;
    EXPECT_EQ(load(oneTriangleGltf("tri.bin"), t), "");
    EXPECT_EQ(notesWith(t, "POSITION has no min/max"), 1);
}

namespace {

/// Two triangles with normalized unsigned-short POSITION (KHR_mesh_quantization), 8-byte
/// stride, stored values as given; min/max as written into the accessor (stored units).
Scene loadQuantized(const std::vector<std::array<uint16_t, 3>>& v, std::vector<double> lo, std::vector<double> hi) {
    TempDir dir;
    std::string buf;
    for (const auto& p : v) put<uint16_t>(buf, {p[0], p[1], p[2], 0});
    writeFile(dir / "q.bin", buf);
    json doc = withBounds(oneTriangleGltf("q.bin"), std::move(lo), std::move(hi));
    doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    doc["accessors"][0]["componentType"] = 5123;
    doc["accessors"][0]["normalized"] = true;
    doc["accessors"][0]["count"] = v.size();
    doc["bufferViews"][0]["byteStride"] = 8;
    doc["bufferViews"][0]["byteLength"] = buf.size();
    doc["buffers"][0]["byteLength"] = buf.size();
    writeFile(dir / "q.gltf", doc.dump());
    DiskFileSource files;
    Scene s;
    loadGltfModel(s, dir / "q.gltf", DMat4(1.0), files);
    return s;
}

}  // namespace

TEST(GltfInputChecks, QuantizedPositionsAreCheckedAgainstBoundsInStoredUnits) {
    // Issue 14 #7: quantized POSITION declares min/max in the accessor's stored units (here
    // unsigned shorts 0–65535, read normalized to 0–1); they were not checked at all.
    const std::vector<std::array<uint16_t, 3>> good = {{0, 0, 0}, {1000, 0, 0}, {0, 1000, 0}};
    Scene ok = loadQuantized(good, {0, 0, 0}, {1000, 1000, 0});
    EXPECT_EQ(notesWith(ok, "min/max"), 0);
    ASSERT_EQ(ok.geometry.meshes.size(), 1u);
    EXPECT_EQ(ok.geometry.meshes[0].indices.size(), 3u);
    // A corrupt vertex (a flipped high bit: 1000 became 33768) is outside the stored bounds.
    std::vector<std::array<uint16_t, 3>> two = good;
    two.insert(two.end(), {{0, 0, 0}, {33768, 0, 0}, {0, 1000, 0}});
    Scene bad = loadQuantized(two, {0, 0, 0}, {1000, 1000, 0});
    EXPECT_EQ(notesWith(bad, "1 vertices lie outside POSITION's declared min/max"), 1);
    ASSERT_EQ(bad.geometry.meshes.size(), 1u);
    EXPECT_EQ(bad.geometry.meshes[0].indices.size(), 3u);  // the good triangle only
    for (const Vec3& p : bad.geometry.meshes[0].positions) EXPECT_LE(p.x, 1000.f / 65535.f + 1e-6f);
    // Bounds written in the normalized units (0–1) are wrong for this file: both vertices away
    // from the origin lie outside them, and no triangle is left.
    Scene wrong = loadQuantized(good, {0, 0, 0}, {1, 1, 0});
    EXPECT_EQ(notesWith(wrong, "2 vertices lie outside POSITION's declared min/max"), 1);
    for (const auto& m : wrong.geometry.meshes) EXPECT_EQ(m.indices.size(), 0u);
    // Quantized positions without min/max get the note float ones get.
    Scene none = loadQuantized(good, {}, {});
    EXPECT_EQ(notesWith(none, "POSITION has no min/max"), 1);
}

TEST(GltfInputChecks, SceneIndexOutOfRangeIsAnError) {
    json doc = oneTriangleGltf("tri.bin");
    doc["scene"] = 5;
    Scene s;
    const std::string e = load(doc, s);
    EXPECT_NE(e.find("scene: 5 is not one of the file's 1 scenes"), std::string::npos) << e;
}

TEST(GltfInputChecks, MaterialIndexOutOfRangeIsNoted) {
    json doc = oneTriangleGltf("tri.bin");
    doc["meshes"][0]["primitives"][0]["material"] = 3;
    Scene s;
    ASSERT_EQ(load(doc, s), "");
    EXPECT_EQ(notesWith(s, "meshes[0].primitives[0].material: no such material (0 in the file)"), 1);
}

TEST(GltfInputChecks, IndexCountNotAMultipleOfThreeIsNoted) {
    TempDir dir;
    std::string buf = oneTriangleBytes(kA, kB, kC);
    put<uint16_t>(buf, {0, 1, 2, 0, 0, 0});  // 4 indices (8 bytes) + 4 of padding
    writeFile(dir / "b.bin", buf);
    json doc = oneTriangleGltf("b.bin");
    doc["buffers"][0]["byteLength"] = 48;
    doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 8}});
    doc["accessors"].push_back({{"bufferView", 1}, {"componentType", 5123}, {"count", 4}, {"type", "SCALAR"}});
    doc["meshes"][0]["primitives"][0]["indices"] = 1;
    writeFile(dir / "m.gltf", doc.dump());
    DiskFileSource files;
    Scene s;
    loadGltfModel(s, dir / "m.gltf", DMat4(1.0), files);
    EXPECT_EQ(notesWith(s, "1 trailing indices ignored"), 1);
}

TEST(GltfInputChecks, DuplicateJsonKeyIsNoted) {
    std::string text = oneTriangleGltf("tri.bin").dump();
    text.insert(1, "\"scene\": 0,");  // dump() already has "scene": 0
    Scene s;
    ASSERT_EQ(load(json(), s, text), "");
    EXPECT_EQ(notesWith(s, "scene: duplicate JSON key"), 1);
}

// Issue 30 #3: the cycle check walks each node once (walking up from every node was quadratic
// in a chain: 10⁵ nodes took 15 s). A 100,000-node chain loads with the triangle at its end
// moved by every node's translation; the same chain closed into a loop is refused, naming the
// first node whose ancestors loop.
TEST(GltfInputChecks, LongNodeChainLoadsAndItsCycleIsFound) {
    const int n = 100000;
    json doc = oneTriangleGltf("tri.bin");
    json nodes = json::array();
    for (int i = 0; i + 1 < n; ++i) nodes.push_back({{"children", {i + 1}}, {"translation", {0.0, 0.0, 0.5}}});
    nodes.push_back(doc["nodes"][0]);
    doc["nodes"] = nodes;
    Scene s;
    ASSERT_EQ(load(doc, s), "");
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    EXPECT_FLOAT_EQ(s.geometry.meshes[0].positions[0].z, 0.5f * (n - 1));

    // Node 0 and 1 stay outside the loop: 1 → 2 → ... → n-1 → 2.
    doc["nodes"][n - 1]["children"] = {2};
    Scene c;
    const std::string e = load(doc, c);
    EXPECT_NE(e.find("nodes[2] has more than one parent"), std::string::npos) << e;
    doc["nodes"][1]["children"] = json::array();  // now 2 → ... → n-1 → 2 is a loop with no way in
    Scene d;
    const std::string e2 = load(doc, d);
    EXPECT_NE(e2.find("nodes[2]: the node hierarchy has a cycle"), std::string::npos) << e2;
}
