// KHR_mesh_quantization: every component type the extension allows, for every attribute it
// covers, loads as the extension and the core specification's normalization rules define it.
// POSITION and TEXCOORD_n: byte, unsigned byte, short, unsigned short, normalized or not.
// NORMAL and TANGENT: normalized byte and short. Each case is one triangle whose attribute is
// stored in that type (elements padded to 4 bytes, as glTF asks of vertex attributes); the
// loaded values are compared with the integers decoded by hand: c/127 (and −128 → −1), c/255,
// c/32767 (−32768 → −1), c/65535 when normalized, the integers themselves when not.
#include <gtest/gtest.h>

#include "engine/util/file_source.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
using namespace gltftest;

namespace {

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kFloat = 5126;

int componentSize(int type) { return type == kByte || type == kUByte ? 1 : type == kShort || type == kUShort ? 2 : 4; }

/// A stored integer (or float) as the specification decodes it.
double decoded(int type, bool normalized, double stored) {
    if (type == kFloat || !normalized) return stored;
    switch (type) {
        case kByte: return std::max(stored / 127.0, -1.0);
        case kUByte: return stored / 255.0;
        case kShort: return std::max(stored / 32767.0, -1.0);
        default: return stored / 65535.0;
    }
}

/// Appends `count` elements of `comps` stored values each, every element padded to 4 bytes.
void store(std::string& buf, int type, int comps, const std::vector<double>& values, int& stride) {
    const int size = componentSize(type);
    stride = (comps * size + 3) / 4 * 4;
    for (size_t e = 0; e < values.size() / size_t(comps); ++e) {
        std::string elem;
        for (int c = 0; c < comps; ++c) {
            const double v = values[e * size_t(comps) + size_t(c)];
            switch (type) {
                case kByte: put<int8_t>(elem, {int8_t(v)}); break;
                case kUByte: put<uint8_t>(elem, {uint8_t(v)}); break;
                case kShort: put<int16_t>(elem, {int16_t(v)}); break;
                case kUShort: put<uint16_t>(elem, {uint16_t(v)}); break;
                default: put<float>(elem, {float(v)}); break;
            }
        }
        elem.resize(size_t(stride), '\0');
        buf += elem;
    }
}

struct Attribute {
    std::string name;
    int type;
    bool normalized;
    int comps;
    std::vector<double> values;  ///< stored, three elements
};

/// One triangle: POSITION as given or float (0,0,0), (1,0,0), (0,1,0); the tested attribute.
TriangleMesh loadTriangle(const Attribute& a) {
    std::string buf;
    json views = json::array(), accessors = json::array(), attributes = json::object();
    auto add = [&](const std::string& name, int type, bool normalized, int comps, const std::vector<double>& v) {
        while (buf.size() % 4) buf += '\0';
        const size_t at = buf.size();
        int stride = 0;
        store(buf, type, comps, v, stride);
        views.push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", buf.size() - at}, {"byteStride", stride}});
        json acc = {{"bufferView", views.size() - 1}, {"componentType", type}, {"count", 3},
                    {"type", comps == 2 ? "VEC2" : comps == 3 ? "VEC3" : "VEC4"}};
        if (normalized) acc["normalized"] = true;
        if (name == "POSITION") {
            acc["min"] = json::array();
            acc["max"] = json::array();
            for (int c = 0; c < 3; ++c) {
                double lo = v[size_t(c)], hi = lo;
                for (int e = 1; e < 3; ++e) lo = std::min(lo, v[size_t(e * 3 + c)]), hi = std::max(hi, v[size_t(e * 3 + c)]);
                acc["min"].push_back(lo);
                acc["max"].push_back(hi);
            }
        }
        accessors.push_back(acc);
        attributes[name] = accessors.size() - 1;
    };
    if (a.name != "POSITION") add("POSITION", kFloat, false, 3, {0, 0, 0, 1, 0, 0, 0, 1, 0});
    add(a.name, a.type, a.normalized, a.comps, a.values);
    json g{{"asset", {{"version", "2.0"}}},
           {"extensionsUsed", {"KHR_mesh_quantization"}},
           {"extensionsRequired", {"KHR_mesh_quantization"}},
           {"scene", 0},
           {"scenes", {{{"nodes", {0}}}}},
           {"nodes", {{{"mesh", 0}}}},
           {"meshes", {{{"primitives", {{{"attributes", attributes}}}}}}},
           {"accessors", accessors},
           {"bufferViews", views},
           {"buffers", {{{"uri", dataUri(buf)}, {"byteLength", buf.size()}}}}};
    TempDir dir;
    writeFile(dir / "q.gltf", g.dump());
    DiskFileSource files;
    Scene s;
    loadGltfModel(s, dir / "q.gltf", DMat4(1.0), files);
    if (s.geometry.meshes.size() != 1) throw std::runtime_error("expected one mesh");
    return s.geometry.meshes[0];
}

std::string caseName(const Attribute& a) {
    return a.name + " componentType " + std::to_string(a.type) + (a.normalized ? " normalized" : "");
}

}  // namespace

TEST(MeshQuantization, PositionsAndTexcoordsInEveryIntegerTypeNormalizedOrNot) {
    int cases = 0;
    for (int type : {kByte, kUByte, kShort, kUShort})
        for (bool normalized : {false, true})
            for (const char* name : {"POSITION", "TEXCOORD_0"}) {
                const bool position = std::string(name) == "POSITION";
                const bool isSigned = type == kByte || type == kShort;
                const double big = type == kByte ? 127 : type == kUByte ? 255 : type == kShort ? 32767 : 65535;
                // A corner at the type's extreme; a negative one (the most negative for normalized
                // signed types, which decodes to exactly −1) where the type is signed.
                const double low = isSigned ? (normalized ? (type == kByte ? -128 : -32768) : -7) : 3;
                Attribute a{name, type, normalized, position ? 3 : 2,
                            position ? std::vector<double>{0, 0, low, big, 0, 0, 0, big, 5}
                                     : std::vector<double>{0, low, big, 1, 2, big}};
                const TriangleMesh m = loadTriangle(a);
                SCOPED_TRACE(caseName(a));
                const std::vector<Vec3> want3 = {Vec3(0, 0, float(decoded(type, normalized, low))),
                                                 Vec3(float(decoded(type, normalized, big)), 0, 0),
                                                 Vec3(0, float(decoded(type, normalized, big)), float(decoded(type, normalized, 5)))};
                const std::vector<Vec2> want2 = {Vec2(0, float(decoded(type, normalized, low))), Vec2(float(decoded(type, normalized, big)), float(decoded(type, normalized, 1))),
                                                 Vec2(float(decoded(type, normalized, 2)), float(decoded(type, normalized, big)))};
                ASSERT_EQ(m.indices.size(), 3u);
                for (int i = 0; i < 3; ++i) {
                    const uint32_t v = m.indices[size_t(i)];  // corners in the file's order
                    // Within a float's rounding of the quotient (the loader divides in float).
                    if (position) {
                        for (int c = 0; c < 3; ++c)
                            EXPECT_NEAR(m.positions[v][c], want3[size_t(i)][c], 1e-6 * std::max(1.f, std::abs(want3[size_t(i)][c])))
                                << "corner " << i;
                    } else {
                        ASSERT_EQ(m.uvs.size(), 3u);
                        for (int c = 0; c < 2; ++c)
                            EXPECT_NEAR(m.uvs[v][c], want2[size_t(i)][c], 1e-6 * std::max(1.f, std::abs(want2[size_t(i)][c])))
                                << "corner " << i;
                    }
                }
                if (normalized && isSigned) {
                    EXPECT_EQ(position ? m.positions[m.indices[0]].z : m.uvs[m.indices[0]].y, -1.f);
                }
                ++cases;
            }
    EXPECT_EQ(cases, 16);
}

TEST(MeshQuantization, NormalsAndTangentsInNormalizedBytesAndShorts) {
    for (int type : {kByte, kShort}) {
        const double one = type == kByte ? 127 : 32767;
        // Normals: +z, a diagonal (0.6, 0, 0.8) as the type rounds it, and −z's neighbour.
        const std::vector<double> n = {0, 0, one, std::round(0.6 * one), 0, std::round(0.8 * one), 0, std::round(0.3 * one), one};
        const TriangleMesh mn = loadTriangle({"NORMAL", type, true, 3, n});
        SCOPED_TRACE(type);
        for (int i = 0; i < 3; ++i) {
            const Vec3 stored(float(n[size_t(3 * i)] / one), float(n[size_t(3 * i + 1)] / one), float(n[size_t(3 * i + 2)] / one));
            const Vec3 got = mn.normals[mn.indices[size_t(i)]];
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], glm::normalize(stored)[c], 1e-6f) << "normal " << i;
        }
        // Tangents: xyz and the handedness w = ±1.
        const std::vector<double> t = {one, 0, 0, one, 0, one, 0, -one, std::round(0.6 * one), std::round(0.8 * one), 0, one};
        const TriangleMesh mt = loadTriangle({"TANGENT", type, true, 4, t});
        ASSERT_EQ(mt.tangents.size(), 3u);
        for (int i = 0; i < 3; ++i) {
            const Vec3 stored(float(t[size_t(4 * i)] / one), float(t[size_t(4 * i + 1)] / one), float(t[size_t(4 * i + 2)] / one));
            const Vec4 got = mt.tangents[mt.indices[size_t(i)]];
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], glm::normalize(stored)[c], 1e-6f) << "tangent " << i;
            EXPECT_EQ(got.w, i == 1 ? -1.f : 1.f) << "tangent " << i;
        }
    }
}
