// glTF geometry on hand-made files whose results are worked out by hand: node hierarchies,
// mirroring and non-uniform scale, strips and fans, quantized/normalized/sparse accessors,
// generated normals, and dropped degenerate triangles.
#include <gtest/gtest.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_geometry.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
using namespace gltftest;

namespace {

/// A glTF with one mesh primitive from raw buffer bytes, accessors and nodes given by the test.
json model(const std::string& buffer, json accessors, json bufferViews, json primitive, json nodes, json rootNodes = {0}) {
    return json{{"asset", {{"version", "2.0"}}},
                {"scene", 0},
                {"scenes", {{{"nodes", rootNodes}}}},
                {"nodes", nodes},
                {"meshes", {{{"primitives", {primitive}}}}},
                {"accessors", accessors},
                {"bufferViews", bufferViews},
                {"buffers", {{{"uri", dataUri(buffer)}, {"byteLength", buffer.size()}}}}};
}

Scene load(const json& g, DVec3 renderOrigin = DVec3(0.0)) {
    TempDir dir;
    writeFile(dir / "m.gltf", g.dump());
    DiskFileSource files;
    Scene s;
    s.renderOrigin = renderOrigin;
    loadGltfModel(s, dir / "m.gltf", DMat4(1.0), files);
    return s;
}

Vec3 faceNormal(const TriangleMesh& m, size_t t) {
    const Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]], c = m.positions[m.indices[3 * t + 2]];
    return glm::normalize(glm::cross(b - a, c - a));
}

void expectNear(const Vec3& got, const Vec3& want, float tol = 1e-5f) {
    EXPECT_NEAR(got.x, want.x, tol);
    EXPECT_NEAR(got.y, want.y, tol);
    EXPECT_NEAR(got.z, want.z, tol);
}

json floatTriangle(std::string& buf, std::initializer_list<float> xyz9, std::initializer_list<float> normals9 = {}) {
    put<float>(buf, xyz9);
    json accessors = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}};
    if (normals9.size()) {
        put<float>(buf, normals9);
        accessors.push_back({{"bufferView", 0}, {"byteOffset", 36}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}});
    }
    return accessors;
}

}  // namespace

TEST(GltfGeometry, NodeHierarchyPlacesVerticesInRenderSpace) {
    // Parent: translation (10, 0, 0). Child: translation (0, 2, 0), a quarter turn about +y,
    // which takes (x, y, z) to (z, y, −x).
    std::string buf;
    json acc = floatTriangle(buf, {1, 0, 0, 0, 1, 0, 0, 0, 1});
    const double h = std::sqrt(0.5);
    json nodes = {{{"translation", {10, 0, 0}}, {"children", {1}}},
                  {{"translation", {0, 2, 0}}, {"rotation", {0, h, 0, h}}, {"mesh", 0}}};
    const Scene s = load(model(buf, acc, {{{"buffer", 0}, {"byteLength", 36}}}, {{"attributes", {{"POSITION", 0}}}}, nodes),
                         DVec3(64, 0, 0));
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    const TriangleMesh& m = s.geometry.meshes[0];
    expectNear(m.positions[0], Vec3(10 - 64, 2, -1));
    expectNear(m.positions[1], Vec3(10 - 64, 3, 0));
    expectNear(m.positions[2], Vec3(11 - 64, 2, 0));
    EXPECT_EQ(m.node, -1) << "nothing animates it: baked";
    ASSERT_EQ(s.geometry.models.size(), 1u);
    EXPECT_EQ(s.geometry.models[0].nodes[1].parent, 0);
    EXPECT_DOUBLE_EQ(s.geometry.models[0].nodes[1].translation.y, 2.0);
}

TEST(GltfGeometry, FarAwayModelKeepsItsPrecision) {
    // A model at x = 6.4e6 (stability case 22): with the render origin there, vertices 1e-3
    // apart stay distinct, as they would not in float world coordinates.
    std::string buf;
    json acc = floatTriangle(buf, {0, 0, 0, 1e-3f, 0, 0, 0, 1e-3f, 0});
    json nodes = {{{"translation", {6.4e6, 0, 0}}, {"mesh", 0}}};
    const Scene s = load(model(buf, acc, {{{"buffer", 0}, {"byteLength", 36}}}, {{"attributes", {{"POSITION", 0}}}}, nodes),
                         DVec3(6.4e6, 0, 0));
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    expectNear(s.geometry.meshes[0].positions[1], Vec3(1e-3f, 0, 0), 1e-9f);
}

TEST(GltfGeometry, MirroringFlipsWindingAndNonUniformScaleUsesInverseTranspose) {
    // Triangle in the plane x + y = 1 with its normal (1, 1, 0)/√2, given both by winding and by
    // NORMAL. Under scale (−2, 1, 1) the plane becomes −x/2 + y = 1: normal ∝ (−0.5, 1, 0),
    // and the mirror must not turn the front face around.
    std::string buf;
    const float n = std::sqrt(0.5f);
    json acc = floatTriangle(buf, {1, 0, 0, 0, 1, 0, 0, 1, 1}, {n, n, 0, n, n, 0, n, n, 0});
    json views = {{{"buffer", 0}, {"byteLength", 72}}};
    json prim = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}};
    const Vec3 want = glm::normalize(Vec3(-0.5f, 1.f, 0.f));
    for (json scale : {json{-2, 1, 1}, json{2, 1, 1}}) {
        const Scene s = load(model(buf, acc, views, prim, {{{"scale", scale}, {"mesh", 0}}}));
        ASSERT_EQ(s.geometry.meshes.size(), 1u);
        const Vec3 w = scale[0] == -2 ? want : glm::normalize(Vec3(0.5f, 1.f, 0.f));
        expectNear(s.geometry.meshes[0].normals[0], w);
        expectNear(faceNormal(s.geometry.meshes[0], 0), w);  // winding agrees with the normal
    }
}

TEST(GltfGeometry, StripsAndFansBecomeTrianglesWithOneWinding) {
    // The glTF Asset Generator's unit squares facing +z, in every triangle mode, indexed or not.
    const std::string dir = "/usr/share/assimp/models/glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/";
    for (const char* f : {"04", "05", "06", "11", "12", "13"}) {
        DiskFileSource files;
        Scene s;
        loadGltfModel(s, dir + "Mesh_PrimitiveMode_" + f + ".gltf", DMat4(1.0), files);
        size_t tris = 0;
        double area = 0.0;
        for (const TriangleMesh& m : s.geometry.meshes)
            for (size_t t = 0; t < m.triangleCount(); ++t, ++tris) {
                const Vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]], c = m.positions[m.indices[3 * t + 2]];
                const Vec3 cr = glm::cross(b - a, c - a);
                area += 0.5 * glm::length(cr);
                EXPECT_GT(cr.z, 0.f) << f << ": triangle " << t << " faces away";
            }
        const Aabb b = s.geometry.bounds();
        EXPECT_EQ(tris, 2u) << f;
        EXPECT_NEAR(area, double(b.hi.x - b.lo.x) * (b.hi.y - b.lo.y), 1e-6) << f << ": the two triangles tile the square";
    }
}

TEST(GltfGeometry, PointsAndLinesOfEveryModeBecomeDotsAndCapsules) {
    // The glTF Asset Generator's unit square outlined in POINTS, LINES, LINE_LOOP and LINE_STRIP,
    // indexed (07–10) or not (00–03): each loads (before, all eight were refused as having
    // nothing to render), every generated vertex lies one radius from a vertex of the file, and
    // the drawing stays in the square's plane within that radius.
    const std::string dir = "/usr/share/assimp/models/glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/";
    for (const char* f : {"00", "01", "02", "03", "07", "08", "09", "10"}) {
        DiskFileSource files;
        const Scene s = loadGltfScene(dir + "Mesh_PrimitiveMode_" + f + ".gltf", files);
        ASSERT_FALSE(s.geometry.meshes.empty()) << f;
        int notes = 0;
        for (const std::string& n : s.notes) notes += n.find("drawn as dots and lines") != std::string::npos;
        EXPECT_EQ(notes, 1) << f;
        const Aabb b = s.geometry.bounds();
        const float width = b.hi.x - b.lo.x, depth = b.hi.z - b.lo.z;
        EXPECT_GT(width, 0.9f) << f << ": the unit square's outline";
        // Thin: 1.5 pixels of a 294-pixel diagonal, so well under 1% of the square's side.
        EXPECT_LT(depth, 0.01f * width) << f;
        EXPECT_GT(depth, 0.f) << f << ": a dot or a line has a thickness";
    }
}

TEST(GltfGeometry, WireGeometryKeepsEachVertexsAttributesOneRadiusAway) {
    gltf::PrimitiveGeometry g;
    g.wire = true;
    g.mesh.positions = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 3, 0)};
    g.mesh.colors = {Vec4(1, 0, 0, 1), Vec4(0, 1, 0, 1), Vec4(0, 0, 1, 0.5f)};
    g.wirePoints = {0, 1, 2};
    g.wireSegments = {0, 1, 1, 2};
    const float r = 0.05f;
    const gltf::PrimitiveGeometry w = gltf::wireGeometry(g, r);
    const TriangleMesh& m = w.mesh;
    EXPECT_FALSE(w.wire);
    // Three octahedra (6 vertices, 8 faces) and two six-sided tubes (12 vertices, 12 faces).
    EXPECT_EQ(m.positions.size(), 3u * 6 + 2u * 12);
    EXPECT_EQ(m.triangleCount(), 3u * 8 + 2u * 12);
    ASSERT_EQ(m.colors.size(), m.positions.size());
    ASSERT_EQ(m.normals.size(), m.positions.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
        // The vertex it grew from: the one of the same colour.
        int from = -1;
        for (int k = 0; k < 3; ++k)
            if (m.colors[i] == g.mesh.colors[size_t(k)]) from = k;
        ASSERT_GE(from, 0) << i;
        EXPECT_NEAR(glm::length(m.positions[i] - g.mesh.positions[size_t(from)]), r, 1e-5f) << i;
        EXPECT_NEAR(glm::length(m.normals[i]), 1.f, 1e-5f) << i;
        EXPECT_NEAR(glm::dot(m.normals[i], m.positions[i] - g.mesh.positions[size_t(from)]), r, 1e-5f) << i << ": normals point out";
    }
    // Every face winds counter-clockwise seen from outside: its normal agrees with its corners'.
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        const uint32_t a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2];
        const Vec3 n = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        EXPECT_GT(glm::dot(n, m.normals[a] + m.normals[b] + m.normals[c]), 0.f) << "face " << t;
    }
}

TEST(GltfGeometry, QuantizedNormalizedAndSparseAccessorsDecode) {
    // POSITION: unsigned bytes, not normalized (KHR_mesh_quantization), stride 4 with padding;
    // a sparse accessor replaces vertex 1 with (4, 0, 0). NORMAL: normalized signed bytes, where
    // −128 clamps to −1. TEXCOORD_0: normalized unsigned shorts.
    std::string buf;
    put<uint8_t>(buf, {0, 0, 0, 99, 2, 0, 0, 99, 0, 2, 0, 99});           // 0..11: positions
    put<int8_t>(buf, {0, 0, 127, 0, 0, -128, 0, 0, 0, 127, 0, 0});        // 12..23: normals, stride 4
    put<uint16_t>(buf, {0, 0, 65535, 0, 32768, 65535});                   // 24..35: uvs
    put<uint8_t>(buf, {1});                                               // 36: sparse index
    put<uint8_t>(buf, {4, 0, 0});                                         // 37..39: sparse value
    json views = {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 12}, {"byteStride", 4}},
                  {{"buffer", 0}, {"byteOffset", 12}, {"byteLength", 12}, {"byteStride", 4}},
                  {{"buffer", 0}, {"byteOffset", 24}, {"byteLength", 12}},
                  {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 1}},
                  {{"buffer", 0}, {"byteOffset", 37}, {"byteLength", 3}}};
    json acc = {{{"bufferView", 0}, {"componentType", 5121}, {"count", 3}, {"type", "VEC3"},
                 {"sparse", {{"count", 1}, {"indices", {{"bufferView", 3}, {"componentType", 5121}}}, {"values", {{"bufferView", 4}}}}}},
                {{"bufferView", 1}, {"componentType", 5120}, {"normalized", true}, {"count", 3}, {"type", "VEC3"}},
                {{"bufferView", 2}, {"componentType", 5123}, {"normalized", true}, {"count", 3}, {"type", "VEC2"}}};
    json prim = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}};
    json g = model(buf, acc, views, prim, {{{"mesh", 0}}});
    g["extensionsUsed"] = {"KHR_mesh_quantization"};
    g["extensionsRequired"] = {"KHR_mesh_quantization"};
    const Scene s = load(g);
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    const TriangleMesh& m = s.geometry.meshes[0];
    expectNear(m.positions[0], Vec3(0, 0, 0));
    expectNear(m.positions[1], Vec3(4, 0, 0));
    expectNear(m.positions[2], Vec3(0, 2, 0));
    expectNear(m.normals[0], Vec3(0, 0, 1));
    expectNear(m.normals[1], Vec3(0, -1, 0));
    expectNear(m.normals[2], Vec3(0, 1, 0));
    EXPECT_FLOAT_EQ(m.uvs[1].x, 1.f);
    EXPECT_FLOAT_EQ(m.uvs[2].x, 32768.f / 65535.f);
    EXPECT_FLOAT_EQ(m.uvs[2].y, 1.f);
}

TEST(GltfGeometry, MissingNormalsAreAreaWeightedWhenIndexedAndFlatOtherwise) {
    // Triangle A (0,0,0),(1,0,0),(0,1,0): normal +z, twice-area 1. Triangle B (0,1,0),(0,0,0),
    // (0,0,2): normal −x, twice-area 2. Shared vertices get normalize((0,0,1) + (−2,0,0)).
    std::string buf;
    put<float>(buf, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 2});
    put<uint16_t>(buf, {0, 1, 2, 2, 0, 3});
    json views = {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}};
    json acc = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}};
    const Scene s = load(model(buf, acc, views, {{"attributes", {{"POSITION", 0}}}, {"indices", 1}}, {{{"mesh", 0}}}));
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    const Vec3 shared = glm::normalize(Vec3(-2, 0, 1));
    expectNear(s.geometry.meshes[0].normals[0], shared);
    expectNear(s.geometry.meshes[0].normals[2], shared);
    expectNear(s.geometry.meshes[0].normals[1], Vec3(0, 0, 1));
    expectNear(s.geometry.meshes[0].normals[3], Vec3(-1, 0, 0));

    // Non-indexed: each triangle owns its corners, so normals are flat.
    std::string flat;
    put<float>(flat, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 2});
    const Scene f = load(model(flat, {{{"bufferView", 0}, {"componentType", 5126}, {"count", 6}, {"type", "VEC3"}}},
                               {{{"buffer", 0}, {"byteLength", 72}}}, {{"attributes", {{"POSITION", 0}}}}, {{{"mesh", 0}}}));
    for (int i = 0; i < 3; ++i) expectNear(f.geometry.meshes[0].normals[i], Vec3(0, 0, 1));
    for (int i = 3; i < 6; ++i) expectNear(f.geometry.meshes[0].normals[i], Vec3(-1, 0, 0));
}

TEST(GltfGeometry, DegenerateTrianglesAreDroppedAndCounted) {
    std::string buf;
    put<float>(buf, {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0});
    put<uint16_t>(buf, {0, 1, 2, 0, 0, 1, 0, 1, 3});  // good, repeated index, collinear
    json views = {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 18}}};
    json acc = {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                {{"bufferView", 1}, {"componentType", 5123}, {"count", 9}, {"type", "SCALAR"}}};
    const Scene s = load(model(buf, acc, views, {{"attributes", {{"POSITION", 0}}}, {"indices", 1}}, {{{"mesh", 0}}}));
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    EXPECT_EQ(s.geometry.meshes[0].triangleCount(), 1u);
    bool noted = false;
    for (const std::string& n : s.notes) noted |= n.find("2 degenerate triangles dropped") != std::string::npos;
    EXPECT_TRUE(noted);
}

TEST(GltfGeometry, AnimatedNodesKeepModelSpaceDataForTheAnimator) {
    // Node 1 hangs under node 0, which a translation channel targets: its mesh must stay movable.
    std::string buf;
    json acc = floatTriangle(buf, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    put<float>(buf, {0, 1});          // 36: key times
    put<float>(buf, {0, 0, 0, 5, 0, 0});  // 44: translations
    acc.push_back({{"bufferView", 1}, {"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}});
    acc.push_back({{"bufferView", 2}, {"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
    json views = {{{"buffer", 0}, {"byteLength", 36}}, {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 8}},
                  {{"buffer", 0}, {"byteOffset", 44}, {"byteLength", 24}}};
    json g = model(buf, acc, views, {{"attributes", {{"POSITION", 0}}}},
                   {{{"children", {1}}}, {{"translation", {0, 0, 3}}, {"mesh", 0}}});
    g["animations"] = {{{"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}},
                        {"samplers", {{{"input", 1}, {"output", 2}, {"interpolation", "STEP"}}}}}};
    Scene s = load(g);
    ASSERT_EQ(s.geometry.meshes.size(), 1u);
    EXPECT_EQ(s.geometry.meshes[0].node, 1);
    EXPECT_EQ(s.geometry.meshes[0].model, 0);
    ASSERT_EQ(s.geometry.meshes[0].objectPositions.size(), 3u);
    expectNear(s.geometry.meshes[0].objectPositions[1], Vec3(1, 0, 0));
    expectNear(s.geometry.meshes[0].positions[1], Vec3(1, 0, 3));
    const AnimSampler& smp = s.geometry.models[0].animations[0].samplers[0];
    EXPECT_EQ(smp.interpolation, KeyInterpolation::Step);
    EXPECT_EQ(smp.components, 3);
    EXPECT_EQ(smp.values, (std::vector<float>{0, 0, 0, 5, 0, 0}));
    // The animator's result for the key at t = 1: node 0 at (5, 0, 0).
    const DMat4 n0 = glm::translate(DMat4(1.0), glm::dvec3(5, 0, 0));
    const DMat4 n1 = n0 * glm::translate(DMat4(1.0), glm::dvec3(0, 0, 3));
    s.build();
    s.geometry.applyNodeTransforms(0, {n0, n1});
    expectNear(s.geometry.meshes[0].positions[1], Vec3(6, 0, 3));
}

TEST(GltfGeometry, GeneratedTangentsFollowTheUvGradient) {
    // A quad in the xy plane with u along +x and v along −y, so the image's top (v = 0) is at
    // y = 1. glTF normal maps mean +X = increasing u and +Y = up in the image: the tangent is
    // +x and the bitangent cross(n, t)·w must be +y, so w = +1.
    const std::vector<Vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<Vec3> n(4, Vec3(0, 0, 1));
    const std::vector<Vec2> uv = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    const std::vector<Vec4> t = gltf::generateTangents(p, n, uv, {0, 1, 2, 0, 2, 3});
    for (const Vec4& v : t) {
        expectNear(Vec3(v), Vec3(1, 0, 0));
        EXPECT_EQ(v.w, 1.f);
    }
    // Mirroring the v direction flips the handedness only.
    const std::vector<Vec2> flipped = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const Vec4& v : gltf::generateTangents(p, n, flipped, {0, 1, 2, 0, 2, 3})) {
        expectNear(Vec3(v), Vec3(1, 0, 0));
        EXPECT_EQ(v.w, -1.f);
    }
}
