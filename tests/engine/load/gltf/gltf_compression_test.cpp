// Compressed geometry renders like the plain file: Debian's Draco 2CylinderEngine against the
// uncompressed one, and gltfpack's meshopt (-cc) and quantized (KHR_mesh_quantization) copies of
// the project's own models against their sources, scored by SSIM on the model's pixels (the
// bounding box of the plain render's coverage). Broken compressed data is refused in one line.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/util/image.h"
#include "engine/util/image_metrics.h"
#include "engine/integrators/render.h"

using namespace rf;
using namespace gltftest;

namespace {

const std::string kGltf2 = "/usr/share/assimp/models/glTF2/";

struct Picture {
    int w = 0, h = 0;
    std::vector<uint8_t> rgb;
    std::vector<float> alpha;
};

/// The bare model's default view at 200×150, 4 spp, a fixed exposure, over a transparent
/// background (alpha marks the model's pixels).
Picture renderModel(const std::string& path, std::vector<std::string>* notes = nullptr) {
    DiskFileSource files;
    SceneOptions o;
    o.width = 200;
    o.height = 150;
    Scene s = loadGltfScene(path, files, o);
    if (notes) *notes = s.notes;
    s.transparentBackground = true;
    RenderSettings rs = s.settings;
    rs.autoExposure = false;
    rs.exposure = 0.f;
    RayStats stats;
    const Image img = renderFrame(s, {s.camera, rs}, 0, 0, stats);
    return {img.width(), img.height(), toRgb8(img, rs), img.alpha()};
}

std::vector<uint8_t> crop(const Picture& p, int x0, int y0, int x1, int y1) {
    std::vector<uint8_t> out;
    for (int y = y0; y < y1; ++y)
        out.insert(out.end(), p.rgb.begin() + (size_t(y) * p.w + x0) * 3, p.rgb.begin() + (size_t(y) * p.w + x1) * 3);
    return out;
}

/// SSIM of `test` against `plain` over the bounding box of plain's covered pixels; writes both
/// and a false-colour error image when it is below `want`.
double ssimOnModel(const Picture& test, const Picture& plain, const std::string& name, double want) {
    int x0 = plain.w, y0 = plain.h, x1 = 0, y1 = 0;
    for (int y = 0; y < plain.h; ++y)
        for (int x = 0; x < plain.w; ++x)
            if (plain.alpha[size_t(y) * plain.w + x] > 0.f) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
    EXPECT_GT(x1 - x0, 20) << name << ": the model covers nothing";
    if (x1 - x0 <= 20 || y1 - y0 <= 20) return 0.0;
    const std::vector<uint8_t> a = crop(test, x0, y0, x1, y1), b = crop(plain, x0, y0, x1, y1);
    const double ssim = ssimRgb8(a, b, x1 - x0, y1 - y0);
    std::printf("%s: SSIM %.4f on %dx%d model pixels\n", name.c_str(), ssim, x1 - x0, y1 - y0);
    if (ssim < want) {
        const std::string out = std::string(RAYFARM_TEST_OUT) + "/gltf_compression";
        std::filesystem::create_directories(out);
        writePng(out + "/" + name + ".png", plain.w, plain.h, test.rgb);
        writePng(out + "/" + name + "_plain.png", plain.w, plain.h, plain.rgb);
        writePng(out + "/" + name + "_error.png", x1 - x0, y1 - y0, falseColorErrorRgb8(a, b, x1 - x0, y1 - y0, 0.25));
    }
    return ssim;
}

std::string expectRefusedInOneLine(const std::string& path) {
    DiskFileSource files;
    try {
        loadGltfScene(path, files);
        ADD_FAILURE() << path << " loaded";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        EXPECT_EQ(m.rfind(path, 0), 0u) << m;
        return m;
    }
    return "";
}

/// gltfpack's copy of a project model in dir (args: its options); fails the test if it cannot.
std::string gltfpack(const TempDir& dir, const std::string& model, const std::string& args, const std::string& name) {
    const std::string out = dir / name;
    const std::string cmd = "gltfpack -i '" + std::string(RAYFARM_SOURCE_DIR) + "/" + model + "' -o '" + out + "' " + args + " >/dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd << " (gltfpack: tests/install-deps.sh)";
    return out;
}

json glbJson(const std::string& bytes, std::string& bin) {
    uint32_t len = 0;
    std::memcpy(&len, bytes.data() + 12, 4);
    bin = bytes.substr(20 + len + 8);
    return json::parse(bytes.substr(20, len));
}

std::string makeGlb(const json& doc, const std::string& bin) {
    std::string j = doc.dump();
    while (j.size() % 4) j += ' ';
    std::string out = "glTF";
    put<uint32_t>(out, {2u, uint32_t(12 + 8 + j.size() + 8 + bin.size()), uint32_t(j.size()), 0x4E4F534Au});
    out += j;
    put<uint32_t>(out, {uint32_t(bin.size()), 0x004E4942u});
    out += bin;
    return out;
}

}  // namespace

TEST(GltfCompression, DracoEngineRendersLikeThePlainOne) {
    std::vector<std::string> notes;
    const Picture draco = renderModel(kGltf2 + "draco/2CylinderEngine.gltf", &notes);
    const Picture plain = renderModel(kGltf2 + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    for (const std::string& n : notes) EXPECT_EQ(n.find("KHR_draco"), std::string::npos) << n;
    // Draco quantizes positions (here 14 bits) and normals: the silhouette holds, shading moves a little.
    EXPECT_GE(ssimOnModel(draco, plain, "draco_2CylinderEngine", 0.95), 0.95);
}

TEST(GltfCompression, TruncatedOrCorruptDracoDataIsRefusedInOneLine) {
    TempDir dir;
    const std::string src = kGltf2 + "draco/";
    writeFile(dir / "2CylinderEngine.bin", readFile(src + "2CylinderEngine.bin"));
    json g = json::parse(readFile(src + "2CylinderEngine.gltf"));
    const int view = g["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["bufferView"];
    json cut = g;
    cut["bufferViews"][view]["byteLength"] = g["bufferViews"][view]["byteLength"].get<int>() / 2;
    writeFile(dir / "cut.gltf", cut.dump());
    const std::string m = expectRefusedInOneLine(dir / "cut.gltf");
    EXPECT_NE(m.find("meshes[0].primitives[0].extensions.KHR_draco_mesh_compression"), std::string::npos) << m;
    EXPECT_NE(m.find("Draco"), std::string::npos) << m;

    // Garbage in place of the first primitive's Draco stream (past its header).
    std::string bin = readFile(src + "2CylinderEngine.bin");
    const size_t at = g["bufferViews"][view].value("byteOffset", 0), n = g["bufferViews"][view]["byteLength"];
    for (size_t i = at + 16; i < at + n; ++i) bin[i] = char(0xA5 ^ (i * 7));
    writeFile(dir / "garbage/2CylinderEngine.bin", bin);
    writeFile(dir / "garbage/m.gltf", g.dump());
    expectRefusedInOneLine(dir / "garbage/m.gltf");
    // A Draco bufferView past its buffer: the plain bounds check.
    json past = g;
    past["bufferViews"][view]["byteOffset"] = 1 << 20;
    writeFile(dir / "past.gltf", past.dump());
    EXPECT_NE(expectRefusedInOneLine(dir / "past.gltf").find("run past the end of buffer"), std::string::npos);
}

TEST(GltfCompression, ADracoAccessorCountThatDisagreesWithTheDataIsNoted) {
    // The extension requires the accessors' counts to be the decoded ones; a file that declares
    // others still draws what Draco decodes, and says so.
    TempDir dir;
    const std::string src = kGltf2 + "draco/";
    writeFile(dir / "2CylinderEngine.bin", readFile(src + "2CylinderEngine.bin"));
    json g = json::parse(readFile(src + "2CylinderEngine.gltf"));
    json& prim = g["meshes"][0]["primitives"][0];
    const int position = prim["attributes"]["POSITION"], indices = prim["indices"];
    const int declared = g["accessors"][position]["count"];
    g["accessors"][position]["count"] = declared + 5;
    g["accessors"][indices]["count"] = g["accessors"][indices]["count"].get<int>() + 3;
    writeFile(dir / "counts.gltf", g.dump());
    DiskFileSource files;
    const Scene s = loadGltfScene(dir / "counts.gltf", files);
    std::string all;
    for (const std::string& n : s.notes) all += n + "\n";
    const std::string where = "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression";
    EXPECT_NE(all.find(where + ".attributes.POSITION: the accessor declares " + std::to_string(declared + 5) +
                       " vertices, the Draco data decodes " + std::to_string(declared) + "; the decoded count is used"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find(where + ": the index accessor declares"), std::string::npos) << all;
    // The unedited file has no such note.
    const Scene plain = loadGltfScene(src + "2CylinderEngine.gltf", files);
    for (const std::string& n : plain.notes) EXPECT_EQ(n.find("the decoded count is used"), std::string::npos) << n;
}

TEST(GltfCompression, MeshoptAndQuantizedCopiesRenderLikeTheirSources) {
    TempDir dir;
    // Per model: quantization moves texture coordinates by up to half a step, which on
    // textured_spot's fine noise floor, dim under its spot light, costs SSIM it does not cost on
    // pbr_grid's plain materials. Meshopt itself is lossless over the quantized data: its copy
    // must match the quantized one almost exactly.
    const std::vector<std::pair<std::string, double>> models = {{"scenes/pbr_grid/pbr_grid.gltf", 0.97},
                                                                {"tests/reference/textured_spot.gltf", 0.92}};
    for (const auto& [model, want] : models) {
        const std::string name = std::filesystem::path(model).stem().string();
        const Picture plain = renderModel(std::string(RAYFARM_SOURCE_DIR) + "/" + model);
        // -cc: EXT_meshopt_compression (with its filters) over KHR_mesh_quantization's types.
        const std::string meshopt = gltfpack(dir, model, "-cc", name + ".meshopt.glb");
        std::string bin;
        const json doc = glbJson(readFile(meshopt), bin);
        ASSERT_NE(doc.dump().find("EXT_meshopt_compression"), std::string::npos);
        const Picture packed = renderModel(meshopt), quantized = renderModel(gltfpack(dir, model, "", name + ".quant.glb"));
        EXPECT_GE(ssimOnModel(packed, plain, name + "_meshopt", want), want);
        EXPECT_GE(ssimOnModel(quantized, plain, name + "_quantized", want), want);
        EXPECT_GE(ssimOnModel(packed, quantized, name + "_meshopt_vs_quantized", 0.999), 0.999);
        // Other component types: 8-bit texture coordinates and normals, 16-bit positions.
        EXPECT_GE(ssimOnModel(renderModel(gltfpack(dir, model, "-vt 8 -vn 8 -vp 16", name + ".quant8.glb")), plain, name + "_quantized8", want - 0.02),
                  want - 0.02);
    }
}

TEST(GltfCompression, MeshoptStreamWithABadHeaderIsRefusedInOneLine) {
    TempDir dir;
    const std::string packed = gltfpack(dir, "scenes/pbr_grid/pbr_grid.gltf", "-cc", "p.glb");
    std::string bin;
    const json doc = glbJson(readFile(packed), bin);
    bool broke = false;
    for (size_t i = 0; i < doc["bufferViews"].size() && !broke; ++i) {
        const json& v = doc["bufferViews"][i];
        if (!v.contains("extensions") || !v["extensions"].contains("EXT_meshopt_compression")) continue;
        const json& e = v["extensions"]["EXT_meshopt_compression"];
        std::string b = bin;
        b[e.value("byteOffset", 0)] = char(0x55);  // neither a vertex (0xa?) nor an index (0xe?/0xd?) header
        writeFile(dir / "bad.glb", makeGlb(doc, b));
        const std::string m = expectRefusedInOneLine(dir / "bad.glb");
        EXPECT_NE(m.find("bufferViews[" + std::to_string(i) + "].extensions.EXT_meshopt_compression"), std::string::npos) << m;
        EXPECT_NE(m.find("bad header"), std::string::npos) << m;
        broke = true;
    }
    EXPECT_TRUE(broke) << "no meshopt bufferView in gltfpack's file";
    // Truncated: a stream cut to a quarter.
    json cut = doc;
    for (json& v : cut["bufferViews"])
        if (v.contains("extensions") && v["extensions"].contains("EXT_meshopt_compression")) {
            json& e = v["extensions"]["EXT_meshopt_compression"];
            e["byteLength"] = std::max(1, e["byteLength"].get<int>() / 4);
        }
    writeFile(dir / "cut.glb", makeGlb(cut, bin));
    expectRefusedInOneLine(dir / "cut.glb");
}
