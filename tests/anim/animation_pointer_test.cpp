// KHR_animation_pointer (issue 42): a channel whose pointer names a node's translation,
// rotation, scale or weights plays as the plain channel does; light, camera, material,
// texture-transform and KHR_node_visibility pointers set what they name, frame by frame, checked
// analytically (a light keyed 40 -> 160 cd gives 4x the radiance at the key time; a yfov keyed
// covers the pixels its tangent says; a hidden node's pixels show what is behind it); one whose
// target rayfarm does not animate is left out with one note naming it (its keys may be of any
// type); a pointer to something the file lacks, or keys of the wrong type, are refused naming
// both. On scenes/animated_node.gltf (hand-made: a carrier node moving a cube) rewritten with
// pointers, and scenes/animated_pointers.gltf (tests/anim/make_animated_pointers.py).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "anim/gltf_animation.h"
#include "anim/timeline.h"
#include "engine/integrators/render.h"
#include "engine/lights/environment.h"
#include "engine/load/scene_loader.h"
#include "engine/util/errors.h"

namespace rf::anim {
namespace {

using json = nlohmann::json;

std::string outDir() {
    std::string d = RAYFARM_TEST_OUT;
    d += "/animation_pointer";
    std::filesystem::create_directories(d);
    return d;
}

json original() {
    std::ifstream in(std::string(RAYFARM_SOURCE_DIR) + "/scenes/animated_node.gltf");
    return json::parse(in);
}

/// The file with every node channel written as a KHR_animation_pointer channel, a material,
/// and a VEC2 pointer channel to an application's extras of that material (which rayfarm does
/// not follow).
json withPointers(const std::string& firstPointer = "") {
    json g = original();
    g["extensionsUsed"] = {"KHR_animation_pointer"};
    g["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}}}};
    g["meshes"][0]["primitives"][0]["material"] = 0;
    bool first = true;
    for (json& a : g["animations"])
        for (json& c : a["channels"]) {
            json& t = c["target"];
            const std::string ptr = "/nodes/" + std::to_string(t["node"].get<int>()) + "/" + t["path"].get<std::string>();
            t = {{"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", first && !firstPointer.empty() ? firstPointer : ptr}}}}}};
            first = false;
        }
    // A VEC2 accessor over the first 16 bytes of a VEC3 buffer view, keyed at accessor 4's times.
    json acc = {{"bufferView", 5}, {"componentType", 5126}, {"count", 2}, {"type", "VEC2"}};
    g["accessors"].push_back(acc);
    const int offsetKeys = int(g["accessors"].size()) - 1;
    json& move = g["animations"][0];
    move["samplers"].push_back({{"input", 4}, {"output", offsetKeys}, {"interpolation", "LINEAR"}});
    move["channels"].push_back(
        {{"sampler", int(move["samplers"].size()) - 1},
         {"target",
          {{"path", "pointer"},
           {"extensions", {{"KHR_animation_pointer", {{"pointer", "/materials/0/extras/uvWobble"}}}}}}}});
    return g;
}

LoadedScene loadJson(const json& g, const std::string& name, int camera = -1) {
    // Named after the test too: ctest runs the tests of this file in parallel processes.
    const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    const std::string path = outDir() + "/" + test + "-" + name + ".gltf";  // its buffer is a data: URI
    std::ofstream(path) << g.dump();
    DiskFileSource fs;
    SceneOptions o{};
    o.width = 96;
    o.height = 54;
    if (camera >= 0) o.camera = camera;
    return loadScene(path, fs, o);
}

json stage() {
    std::ifstream in(std::string(RAYFARM_SOURCE_DIR) + "/scenes/animated_pointers.gltf");
    return json::parse(in);
}

/// The message of the InputError loading g throws, or "(loaded)".
std::string refusal(const json& g) {
    try {
        loadJson(g, "bad");
    } catch (const InputError& e) {
        return std::string(e.what());
    }
    return std::string("(loaded)");
}

/// How many pixels of a w x h picture through the scene's camera see `material` first (pixel
/// centres; row >= 0: that row alone).
int materialPixels(const Scene& s, int w, int h, int material, int row = -1) {
    const CameraRays rays(s.camera, w, h);
    int n = 0;
    for (int y = row >= 0 ? row : 0; y < (row >= 0 ? row + 1 : h); ++y)
        for (int x = 0; x < w; ++x) {
            Hit hit;
            const Ray r = rays.generate(x + 0.5f, y + 0.5f);
            if (s.geometry.intersect(r, hit)) n += s.geometry.interaction(r, hit).material == material;
        }
    return n;
}

/// The scene at time t of its timeline, lit by its own lights alone: no environment, no ambient,
/// no bounce light, one sample; rendered through its camera at 96x54 (linear radiance).
Image renderAt(const LoadedScene& loaded, double t, Scene* posed = nullptr) {
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    Scene s = loaded.scene;
    tl.apply(s, t);
    s.environment.reset();
    s.environmentBackground = false;
    s.ambientLight = Color(0.f);
    RenderSettings rs = s.settings;
    rs.width = 96, rs.height = 54, rs.spp = 1, rs.bounce = 0;
    RayStats stats;
    Image img = renderFrame(s, {s.camera, rs}, 0, 1, stats);
    if (posed) *posed = s;
    return img;
}

}  // namespace

TEST(AnimationPointer, NodePointersPoseAsThePlainChannelsDo) {
    LoadedScene plain = loadJson(original(), "plain");
    LoadedScene pointers = loadJson(withPointers(), "pointers");
    const SceneGraph& gp = plain.scene.geometry.models[0];
    const SceneGraph& gq = pointers.scene.geometry.models[0];
    for (int a = 0; a < 2; ++a) {
        const GltfAnimationPlayer pp(gp, 0, a, true), pq(gq, 0, a, true);
        EXPECT_EQ(pp.duration(), pq.duration());
        for (double t : {0.0, 0.25, 0.7, 1.5}) {
            std::vector<DMat4> np, nq;
            std::vector<std::vector<double>> wp, wq;
            pp.pose(gp, t, np, wp);
            pq.pose(gq, t, nq, wq);
            ASSERT_EQ(np.size(), nq.size());
            for (size_t n = 0; n < np.size(); ++n)
                for (int c = 0; c < 4; ++c)
                    for (int r = 0; r < 4; ++r) EXPECT_EQ(np[n][c][r], nq[n][c][r]) << "animation " << a << " at " << t << " s, node " << n;
        }
    }
    // The cube moves at all (the comparison is not between two still files).
    std::vector<DMat4> at0, at1;
    std::vector<std::vector<double>> w;
    const GltfAnimationPlayer move(gq, 0, 0, true);
    move.pose(gq, 0.0, at0, w);
    move.pose(gq, 0.7, at1, w);
    EXPECT_NE(at0[0][3], at1[0][3]);
}

TEST(AnimationPointer, AnUnfollowedTargetIsNotedOnceAndItsKeysAreNotRead) {
    const LoadedScene s = loadJson(withPointers(), "pointers");
    int notes = 0, ignored = 0;
    for (const std::string& n : s.scene.notes) {
        notes += n.find("KHR_animation_pointer: 1 channel animates /materials/{}/extras/uvWobble") !=
                 std::string::npos;
        ignored += n.find("extension KHR_animation_pointer ignored") != std::string::npos;
    }
    EXPECT_EQ(notes, 1);
    EXPECT_EQ(ignored, 0);
}

TEST(AnimationPointer, APointerToWhatTheFileLacksIsRefusedNamingBoth) {
    EXPECT_NE(refusal(withPointers("/nodes/7/translation")).find("\"/nodes/7/translation\" names node 7, and the file has 2"),
              std::string::npos);
    json g = withPointers();
    g["animations"][0]["channels"].back()["target"]["extensions"]["KHR_animation_pointer"]["pointer"] = "/materials/3/emissiveFactor";
    EXPECT_NE(refusal(g).find("\"/materials/3/emissiveFactor\" names material 3, and the file has 1"), std::string::npos);
    g["animations"][0]["channels"].back()["target"]["extensions"] = json::object();
    EXPECT_NE(refusal(g).find("KHR_animation_pointer.pointer: missing"), std::string::npos);
}

TEST(AnimationPointer, ALightsKeyedIntensityScalesItsRadianceAndItsColourTints) {
    // Intensity 40 -> 160 cd over 2 s (LINEAR; the film loops it, so 2 s is 0 s again): at 1 s
    // 100 cd, at 1.5 s 130. Lit by that spot alone (its cone, colour and the box's material kept
    // still here), every lit floor pixel's linear radiance scales by the same factor.
    json g = stage();
    json& ch = g["animations"][0]["channels"];
    ch = json::array({ch[0]});
    const LoadedScene loaded = loadJson(g, "stage_intensity", 0);
    Scene posed;
    const Image a = renderAt(loaded, 0.0, &posed), b = renderAt(loaded, 1.0), c = renderAt(loaded, 1.5);
    const CameraRays rays(posed.camera, 96, 54);
    int lit = 0, fx = -1, fy = -1;
    for (int y = 0; y < 54; ++y)
        for (int x = 0; x < 96; ++x) {
            Hit hit;
            const Ray r = rays.generate(x + 0.5f, y + 0.5f);
            if (!posed.geometry.intersect(r, hit) || posed.geometry.interaction(r, hit).material != 0) continue;
            const float r0 = a.pixel(x, y)[0];
            if (!(r0 > 1e-5f)) continue;
            ++lit, fx = x, fy = y;
            EXPECT_NEAR(b.pixel(x, y)[0] / r0, 100.0 / 40.0, 1e-3) << x << "," << y;
            EXPECT_NEAR(c.pixel(x, y)[0] / r0, 130.0 / 40.0, 1e-3) << x << "," << y;
        }
    EXPECT_GT(lit, 20);
    ASSERT_GE(fx, 0);
    // With the colour keyed too (white -> (1, 0.5, 0.1)), at 1 s green is 0.75 of red and blue
    // 0.55 (the floor is grey).
    json t = stage();
    json& tc = t["animations"][0]["channels"];
    tc = json::array({tc[0], tc[1]});
    const LoadedScene tinted = loadJson(t, "stage_tinted", 0);
    const Image d = renderAt(tinted, 1.0, &posed);
    const float* p = d.pixel(fx, fy);
    ASSERT_GT(p[0], 0.f);
    EXPECT_NEAR(p[1] / p[0], 0.75, 1e-3);
    EXPECT_NEAR(p[2] / p[0], 0.55, 1e-3);
    ASSERT_EQ(posed.lights.size(), 1u);
    EXPECT_NEAR(p[0] / b.pixel(fx, fy)[0], 1.0, 1e-3);  // red as bright as with white light
    // The whole stage: the outer cone keyed 0.5 -> 0.2 -> 0.9 over 2 s, never narrower than the
    // inner cone (0.3), which stays.
    const LoadedScene whole = loadJson(stage(), "stage", 0);
    renderAt(whole, 0.5, &posed);
    EXPECT_NEAR(posed.lights[0].outerCone, 0.35f, 1e-6);
    renderAt(whole, 1.0, &posed);
    EXPECT_NEAR(posed.lights[0].outerCone, 0.3f, 1e-6);
    EXPECT_NEAR(posed.lights[0].innerCone, 0.3f, 1e-6);
    EXPECT_NEAR(posed.lights[0].intensity * 683.0, 100.0, 1e-3);
}

TEST(AnimationPointer, AKeyedYfovCoversThePixelsItsTangentSays) {
    // The camera stands still; its yfov goes 0.9 -> 0.6 rad over 2 s (0.675 at 1.5 s). The box's
    // width along one image row is in proportion to 1 / tan(yfov / 2).
    const LoadedScene loaded = loadJson(stage(), "stage", 0);
    auto boxWidth = [&](double t) {
        Scene s;
        renderAt(loaded, t, &s);
        return materialPixels(s, 480, 270, 1, 135);  // the box's
    };
    const int w0 = boxWidth(0.0), w1 = boxWidth(1.5);
    ASSERT_GT(w0, 40);
    EXPECT_NEAR(double(w1) / w0, std::tan(0.45) / std::tan(0.3375), 0.03);
}

TEST(AnimationPointer, AHiddenNodeShowsWhatIsBehindItAndHidesItsLight) {
    // The marker (KHR_node_visibility keyed 1 -> 0 at 1 s, STEP) is drawn before 1 s, not after.
    const LoadedScene loaded = loadJson(stage(), "stage", 0);
    auto markerPixels = [&](double t) {
        Scene s;
        renderAt(loaded, t, &s);
        return materialPixels(s, 96, 54, 2);
    };
    EXPECT_GT(markerPixels(0.5), 10);
    EXPECT_EQ(markerPixels(1.5), 0);
    EXPECT_GT(markerPixels(0.5), 10);  // shown again: a pure function of the time
    // A light on a hidden node gives no light; shown again, its intensity comes back.
    json g = stage();
    g["nodes"][2]["extensions"]["KHR_node_visibility"] = {{"visible", true}};
    g["animations"][0]["channels"][6]["target"]["extensions"]["KHR_animation_pointer"]["pointer"] =
        "/nodes/2/extensions/KHR_node_visibility/visible";
    const LoadedScene lamp = loadJson(g, "hidden_lamp", 0);
    Scene s;
    renderAt(lamp, 1.5, &s);
    EXPECT_EQ(s.lights[0].intensity, 0.f);
    renderAt(lamp, 0.5, &s);
    EXPECT_GT(s.lights[0].intensity, 0.f);
    // A node hidden at rest that no animation shows is not loaded at all.
    json still = stage();
    still["nodes"][4]["extensions"]["KHR_node_visibility"]["visible"] = false;
    still["animations"][0]["channels"].erase(6);
    const LoadedScene gone = loadJson(still, "hidden_marker");
    for (const TriangleMesh& m : gone.scene.geometry.meshes) EXPECT_NE(m.material, 2);
}

TEST(AnimationPointer, MaterialFactorsAndTextureTransformsFollowTheirKeys) {
    json g = stage();
    // A texture transform too: the box gets a base-colour texture (a 1x1 PNG) whose offset is
    // keyed by the base colour's keys read as VEC2s: (0.8, 0.1) at 0 s, (0.1, 1) at 2 s.
    g["images"] = {{{"uri", "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8DwHwAFBQIAX8jx0gAAAABJRU5ErkJggg=="}}};
    g["textures"] = {{{"source", 0}}};
    g["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    const json& colourKeys = g["accessors"][16];
    ASSERT_EQ(colourKeys["type"], "VEC4");
    g["accessors"].push_back({{"bufferView", colourKeys["bufferView"]}, {"componentType", 5126}, {"count", 2}, {"type", "VEC2"}});
    json& show = g["animations"][0];
    show["samplers"].push_back({{"input", 9}, {"output", int(g["accessors"].size()) - 1}});
    show["channels"].push_back(
        {{"sampler", int(show["samplers"].size()) - 1},
         {"target",
          {{"path", "pointer"},
           {"extensions",
            {{"KHR_animation_pointer", {{"pointer", "/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset"}}}}}}}});
    const LoadedScene loaded = loadJson(g, "stage_textured", 0);
    Scene s;
    renderAt(loaded, 1.0, &s);
    const Material& box = s.materials[size_t(s.geometry.meshes[1].material)];
    // Base colour halfway from (0.8, 0.1, 0.1, 1) to (0.1, 0.2, 0.8, 1).
    EXPECT_NEAR(box.color.r, 0.45f, 1e-6);
    EXPECT_NEAR(box.color.g, 0.15f, 1e-6);
    EXPECT_NEAR(box.color.b, 0.45f, 1e-6);
    // Emission = factor (0.2) x strength (0 -> 3: 1.5 at 1 s).
    EXPECT_NEAR(box.emission.r, 0.3f, 1e-6);
    EXPECT_NEAR(box.baseColorTransform.offset.x, 0.45f, 1e-6);
    EXPECT_NEAR(box.baseColorTransform.offset.y, 0.55f, 1e-6);
    const Scene& rest = loaded.scene;
    EXPECT_EQ(rest.materials[size_t(rest.geometry.meshes[1].material)].baseColorTransform.offset, Vec2(0.f, 0.f));
    EXPECT_EQ(rest.materials[size_t(rest.geometry.meshes[1].material)].emission, Color(0.f));
}

TEST(AnimationPointer, KeysOfTheWrongTypeAndImpossibleTargetsAreRefusedNamingBoth) {
    json g = stage();
    // Intensity (a float) keyed by the VEC3 colour accessor.
    g["animations"][0]["samplers"][0]["output"] = g["animations"][0]["samplers"][1]["output"];
    EXPECT_NE(refusal(g).find("is not SCALAR, as the pointer \"/extensions/KHR_lights_punctual/lights/0/intensity\" needs"),
              std::string::npos)
        << refusal(g);
    g = stage();
    g["animations"][0]["samplers"][6]["interpolation"] = "LINEAR";
    EXPECT_NE(refusal(g).find("animates the boolean \"/nodes/4/extensions/KHR_node_visibility/visible\""), std::string::npos)
        << refusal(g);
    g = stage();
    g["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] = "point";
    EXPECT_NE(refusal(g).find("names a spot cone of light 0, which is a point light"), std::string::npos) << refusal(g);
    g = stage();
    g["animations"][0]["channels"][3]["target"]["extensions"]["KHR_animation_pointer"]["pointer"] = "/cameras/0/orthographic/ymag";
    EXPECT_NE(refusal(g).find("names the orthographic projection of camera 0, which is perspective"), std::string::npos)
        << refusal(g);
    g = stage();
    g["animations"][0]["channels"][4]["target"]["extensions"]["KHR_animation_pointer"]["pointer"] =
        "/materials/1/normalTexture/extensions/KHR_texture_transform/offset";
    EXPECT_NE(refusal(g).find("material 1's normalTexture, which the material lacks"), std::string::npos) << refusal(g);
}

TEST(AnimationPointer, AFrameIsAFunctionOfItsTimeAlone) {
    // One scene taken through frames out of order (as a rank handed frames of a resumed film
    // is) ends each one exactly as a fresh copy posed at that time alone: lights (the cone
    // clamped at 1 s, the intensity), the camera's field of view, the material, the marker's
    // visibility. The cone and the visibility are keyed down and back up, so a value left over
    // from an earlier frame would show.
    const LoadedScene loaded = loadJson(stage(), "stage", 0);
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    Scene reused = loaded.scene;
    for (double t : {1.0, 1.5, 0.25, 1.25, 0.0, 0.75, 1.0}) {
        tl.apply(reused, t);
        Scene fresh = loaded.scene;
        tl.apply(fresh, t);
        ASSERT_EQ(reused.lights.size(), fresh.lights.size());
        for (size_t i = 0; i < fresh.lights.size(); ++i) {
            const Light &a = reused.lights[i], &b = fresh.lights[i];
            EXPECT_EQ(a.intensity, b.intensity) << t;
            EXPECT_EQ(a.color, b.color) << t;
            EXPECT_EQ(a.innerCone, b.innerCone) << t;
            EXPECT_EQ(a.outerCone, b.outerCone) << t;
            EXPECT_EQ(a.position, b.position) << t;
        }
        EXPECT_EQ(reused.camera.fovDeg, fresh.camera.fovDeg) << t;
        for (size_t m = 0; m < fresh.materials.size(); ++m) {
            EXPECT_EQ(reused.materials[m].color, fresh.materials[m].color) << t;
            EXPECT_EQ(reused.materials[m].emission, fresh.materials[m].emission) << t;
        }
        EXPECT_EQ(materialPixels(reused, 96, 54, 2), materialPixels(fresh, 96, 54, 2)) << t;
    }
}

TEST(AnimationPointer, ASceneFilesLightTrackOverridesTheModelsKeys) {
    // A scene file that keys light 0's intensity (a glTF light the model's animation keys too)
    // gets its own values: the file's keys are applied first, the scene file's over them.
    const std::string dir = outDir();
    std::ofstream(dir + "/stage_for_scene.gltf") << stage().dump();
    std::ofstream(dir + "/keyed.json") << R"({"camera": {"eye": [0, 2, 6], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45},
  "objects": [{"type": "model", "path": "stage_for_scene.gltf"}],
  "timeline": {"fps": 2, "duration": 2, "animation": true,
               "lights": [{"light": 0, "intensity": [{"time": 0, "value": 0.25}, {"time": 2, "value": 0.75}]}]}})";
    DiskFileSource fs;
    const LoadedScene loaded = loadScene(dir + "/keyed.json", fs);
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    Scene s = loaded.scene;
    tl.apply(s, 1.0);
    ASSERT_FALSE(s.lights.empty());
    EXPECT_NEAR(s.lights[0].intensity, 0.5f, 1e-6);
    // The animation's other keys still play: the colour at 1 s is (1, 0.75, 0.55).
    EXPECT_NEAR(s.lights[0].color.g, 0.75f, 1e-6);
}

TEST(AnimationPointer, ANodeHiddenAtRestStaysHiddenWhenNoAnimationPlays) {
    // The marker hidden at rest, with a point light of its own, and keyed visible before 1 s:
    // the film shows both before 1 s and neither after; a scene file that plays no animation
    // ("animation": false) shows neither.
    json g = stage();
    g["nodes"][4]["extensions"]["KHR_node_visibility"]["visible"] = false;
    g["nodes"][4]["extensions"]["KHR_lights_punctual"] = {{"light", 1}};
    g["extensions"]["KHR_lights_punctual"]["lights"].push_back({{"type", "point"}, {"intensity", 5.0}});
    const LoadedScene film = loadJson(g, "rest_hidden", 0);
    ASSERT_EQ(film.scene.lights.size(), 2u);
    Scene s;
    renderAt(film, 0.5, &s);
    EXPECT_GT(materialPixels(s, 96, 54, 2), 10);
    EXPECT_NEAR(s.lights[1].intensity * 683.0, 5.0, 1e-4);
    renderAt(film, 1.5, &s);
    EXPECT_EQ(materialPixels(s, 96, 54, 2), 0);
    EXPECT_EQ(s.lights[1].intensity, 0.f);

    const std::string dir = outDir();
    std::ofstream(dir + "/rest_hidden_model.gltf") << g.dump();
    std::ofstream(dir + "/rest_hidden_still.json") << R"({"camera": {"eye": [0, 2, 6], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45},
  "objects": [{"type": "model", "path": "rest_hidden_model.gltf"}], "timeline": {"fps": 2, "duration": 1, "animation": false}})";
    DiskFileSource fs;
    const LoadedScene still = loadScene(dir + "/rest_hidden_still.json", fs);
    Scene t = still.scene;
    anim::Timeline::fromScene(still).apply(t, 0.5);
    int marker = -1;  // (a scene file numbers its materials its own way)
    for (size_t m = 0; m < t.materials.size(); ++m)
        if (t.materials[m].name == "Marker") marker = int(m);
    ASSERT_GE(marker, 0);
    EXPECT_EQ(materialPixels(t, 96, 54, marker), 0);
    // (Where a shown marker would be seen through that camera: it is in view.)
    Scene shown = film.scene;
    renderAt(film, 0.5, &shown);
    shown.camera = t.camera;
    EXPECT_GT(materialPixels(shown, 96, 54, 2), 10);
    ASSERT_EQ(t.lights.size(), 2u);
    EXPECT_EQ(t.lights[1].intensity, 0.f);
}

TEST(AnimationPointer, IridescenceFactorsFollowTheirKeys) {
    // KHR_materials_iridescence's factor keyed by the camera's yfov keys (0.9 -> 0.6 over 2 s)
    // and its thickness maximum by the spot's intensity keys (40 -> 160): 0.75 and 100 nm at 1 s;
    // at rest the file's own 1 and 400 nm.
    json g = stage();
    g["extensionsUsed"].push_back("KHR_materials_iridescence");
    g["materials"][1]["extensions"]["KHR_materials_iridescence"] = {{"iridescenceFactor", 1}};
    json& show = g["animations"][0];
    auto key = [&](int sampler, const std::string& field) {
        show["channels"].push_back(
            {{"sampler", sampler},
             {"target",
              {{"path", "pointer"},
               {"extensions", {{"KHR_animation_pointer", {{"pointer", "/materials/1/extensions/KHR_materials_iridescence/" + field}}}}}}}});
    };
    key(3, "iridescenceFactor");
    key(0, "iridescenceThicknessMaximum");
    const LoadedScene loaded = loadJson(g, "stage_film", 0);
    for (const std::string& n : loaded.scene.notes) EXPECT_EQ(n.find("iridescence"), std::string::npos) << n;
    Scene s;
    renderAt(loaded, 1.0, &s);
    const Material& box = s.materials[size_t(s.geometry.meshes[1].material)];
    EXPECT_NEAR(box.iridescence, 0.75f, 1e-6);
    EXPECT_NEAR(box.iridescenceThicknessMax, 100.f, 1e-4);
    const Material& rest = loaded.scene.materials[size_t(loaded.scene.geometry.meshes[1].material)];
    EXPECT_EQ(rest.iridescence, 1.f);
    EXPECT_EQ(rest.iridescenceThicknessMax, 400.f);
}

}  // namespace rf::anim
