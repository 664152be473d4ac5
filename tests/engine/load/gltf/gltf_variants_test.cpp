// KHR_materials_variants and --variant: each primitive shows the material its mapping names for
// the chosen variant and keeps its own where none does; an unknown name, a file without
// variants and a mapping to a material the file lacks are refused in one line; a scene file's
// model key "variant", and --variant over it; and a file Blender 3.4's exporter wrote.
#include <gtest/gtest.h>

#include "engine/util/errors.h"
#include "tests/engine/gltf_floor_scene.h"
#include "engine/load/scene_loader.h"

using namespace rf;
using namespace gltftest;

namespace {

const std::string kBlenderVariants = std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/variants_blender.gltf";

json colour(double r, double g, double b, const char* name) {
    return {{"name", name}, {"pbrMetallicRoughness", {{"baseColorFactor", {r, g, b, 1}}, {"metallicFactor", 0}}}};
}

/// The floor (grey, material 0) with materials red (1) and green (2) and three variants: "red"
/// and "green" map the floor to theirs, "plain" maps nothing.
void addVariants(json& g) {
    g["materials"].push_back(colour(1, 0, 0, "red"));
    g["materials"].push_back(colour(0, 1, 0, "green"));
    g["extensionsUsed"].push_back("KHR_materials_variants");
    g["extensions"]["KHR_materials_variants"] = {{"variants", {{{"name", "red"}}, {{"name", "green"}}, {{"name", "plain"}}}}};
    g["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"] = {
        {"mappings", {{{"material", 1}, {"variants", {0}}}, {{"material", 2}, {"variants", {1}}}}}};
}

Scene floorWith(const std::string& variant, const std::function<void(json&)>& edit = addVariants) {
    SceneOptions o;
    o.assets.variant = variant;
    return loadFloor(colour(0.5, 0.5, 0.5, "grey"), {}, edit, o);
}

Color floorColour(const Scene& s) { return s.materials[size_t(s.geometry.meshes.at(0).material)].color; }

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(MaterialVariants, EachVariantShowsItsMappedMaterialAndTheDefaultIsTheFilesOwn) {
    const Scene plain = floorWith("");
    EXPECT_EQ(floorColour(plain), Color(0.5f));
    bool listed = false;
    for (const std::string& n : plain.notes) listed |= n.find("material variants 3: \"red\", \"green\", \"plain\"") != std::string::npos;
    EXPECT_TRUE(listed) << "a note says which variants the file has";
    EXPECT_EQ(floorColour(floorWith("red")), Color(1.f, 0.f, 0.f));
    EXPECT_EQ(floorColour(floorWith("green")), Color(0.f, 1.f, 0.f));
    EXPECT_EQ(floorColour(floorWith("plain")), Color(0.5f)) << "a variant no mapping names keeps the primitive's own";
    // The picture changes with it: the floor under the light is red, then green.
    const Image red = renderFromAbove(floorWith("red")), green = renderFromAbove(floorWith("green"));
    EXPECT_GT(red.pixel(32, 32)[0], 10.f * red.pixel(32, 32)[1]);
    EXPECT_GT(green.pixel(32, 32)[1], 10.f * green.pixel(32, 32)[0]);
}

TEST(MaterialVariants, UnknownNamesAndBrokenMappingsAreRefusedInOneLine) {
    const std::string unknown = errorOf([] { floorWith("teal"); });
    EXPECT_NE(unknown.find("--variant: no variant named \"teal\" (the file has 3: \"red\", \"green\", \"plain\")"), std::string::npos)
        << unknown;
    EXPECT_EQ(unknown.find('\n'), std::string::npos);
    const std::string none = errorOf([] { floorWith("red", nullptr); });
    EXPECT_NE(none.find("--variant: the file has no material variants (KHR_materials_variants)"), std::string::npos) << none;
    const std::string broken = errorOf([] {
        floorWith("green", [](json& g) {
            addVariants(g);
            g["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][1]["material"] = 7;
        });
    });
    EXPECT_NE(broken.find("meshes[0].primitives[0].extensions.KHR_materials_variants.mappings[1].material: no material 7"),
              std::string::npos)
        << broken;
}

TEST(MaterialVariants, SceneFileKeyAndTheCommandLineOverIt) {
    TempDir dir;
    // One model with variants, one without (Debian's box), side by side.
    const std::function<void(json&)> edit = addVariants;
    {
        // Write the variants floor beside the scene file: loadFloor's own folder goes away.
        std::string buf;
        put<float>(buf, {-10, 0, -10, -10, 0, 10, 10, 0, 10, 10, 0, -10});
        put<uint16_t>(buf, {0, 1, 2, 0, 2, 3});
        json g{{"asset", {{"version", "2.0"}}}, {"extensionsUsed", json::array()}, {"scene", 0}, {"scenes", {{{"nodes", {0}}}}},
               {"nodes", {{{"mesh", 0}}}},
               {"materials", {colour(0.5, 0.5, 0.5, "grey")}},
               {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}}}}}}},
               {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}, {"min", {-10, 0, -10}}, {"max", {10, 0, 10}}},
                              {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
               {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
               {"buffers", {{{"uri", dataUri(buf)}, {"byteLength", buf.size()}}}}};
        edit(g);
        writeFile(dir / "floor.gltf", g.dump());
    }
    const std::string box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    auto scene = [&](const std::string& floorKey, const std::string& cli) {
        const json doc{{"objects", {{{"type", "model"}, {"path", "floor.gltf"}}, {{"type", "model"}, {"path", box}}}}};
        json d = doc;
        if (!floorKey.empty()) d["objects"][0]["variant"] = floorKey;
        writeFile(dir / "s.json", d.dump());
        SceneOptions o;
        o.assets.variant = cli;
        DiskFileSource files;
        return loadScene(dir / "s.json", files, o).scene;
    };
    EXPECT_EQ(floorColour(scene("", "")), Color(0.5f));
    EXPECT_EQ(floorColour(scene("green", "")), Color(0.f, 1.f, 0.f));
    EXPECT_EQ(floorColour(scene("green", "red")), Color(1.f, 0.f, 0.f)) << "--variant wins over the key";
    EXPECT_EQ(floorColour(scene("", "red")), Color(1.f, 0.f, 0.f)) << "and the box without variants keeps its own";
    const std::string keyed = errorOf([&] { scene("teal", ""); });
    EXPECT_NE(keyed.find("objects[0].variant: no variant named \"teal\""), std::string::npos) << keyed;
    // A scene whose only model has no variants refuses --variant; a model key on it too.
    const std::string lone = errorOf([&] {
        writeFile(dir / "b.json", json{{"objects", {{{"type", "model"}, {"path", box}}}}}.dump());
        SceneOptions o;
        o.assets.variant = "red";
        DiskFileSource files;
        loadScene(dir / "b.json", files, o);
    });
    EXPECT_NE(lone.find("--variant: no model in the scene has material variants"), std::string::npos) << lone;
}

TEST(MaterialVariants, AFileBlendersExporterWrote) {
    // tests/reference/variants_blender.py: a cube with a "paint" slot and a sphere, variants
    // "Ruby" and "Jade" mapping the cube's slot to red and green, exported by Blender 3.4.
    DiskFileSource files;
    auto cubeColour = [&](const std::string& variant) {
        SceneOptions o;
        o.assets.variant = variant;
        const Scene s = loadGltfScene(kBlenderVariants, files, o);
        std::vector<Color> colours;
        for (const TriangleMesh& m : s.geometry.meshes) colours.push_back(s.materials[size_t(m.material)].color);
        return colours;
    };
    const std::vector<Color> plain = cubeColour(""), ruby = cubeColour("Ruby"), jade = cubeColour("Jade");
    ASSERT_EQ(plain.size(), 2u);
    // The cube (painted) changes, the sphere (unmapped) does not.
    int changed = 0;
    for (size_t i = 0; i < plain.size(); ++i) {
        if (ruby[i] == plain[i]) {
            EXPECT_EQ(jade[i], plain[i]);
            continue;
        }
        ++changed;
        EXPECT_GT(ruby[i].r, 0.5f);
        EXPECT_LT(ruby[i].g, 0.2f);
        EXPECT_GT(jade[i].g, 0.5f);
        EXPECT_LT(jade[i].r, 0.2f);
    }
    EXPECT_EQ(changed, 1);
    const std::string msg = errorOf([&] { cubeColour("Onyx"); });
    EXPECT_NE(msg.find("no variant named \"Onyx\" (the file has 2: \"Ruby\", \"Jade\")"), std::string::npos) << msg;
}
