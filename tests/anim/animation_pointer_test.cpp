// KHR_animation_pointer (issue 42): a channel whose pointer names a node's translation,
// rotation, scale or weights plays as the plain channel does; one whose target rayfarm does not
// animate is left out with one note naming it (its keys may be of any type: a VEC2 offset was
// refused as "wrong type for this use"); a pointer to something the file lacks is refused
// naming both. On scenes/animated_node.gltf (hand-made: a carrier node moving a cube) rewritten
// with pointers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "anim/gltf_animation.h"
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
/// and a VEC2 pointer channel to that material's texture-transform offset.
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
           {"extensions", {{"KHR_animation_pointer", {{"pointer", "/materials/0/normalTexture/extensions/KHR_texture_transform/offset"}}}}}}}});
    return g;
}

LoadedScene loadJson(const json& g, const std::string& name) {
    const std::string path = outDir() + "/" + name + ".gltf";  // its buffer is a data: URI
    std::ofstream(path) << g.dump();
    DiskFileSource fs;
    return loadScene(path, fs);
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
        notes += n.find("KHR_animation_pointer: 1 channel animates /materials/{}/normalTexture/extensions/KHR_texture_transform/offset") !=
                 std::string::npos;
        ignored += n.find("extension KHR_animation_pointer ignored") != std::string::npos;
    }
    EXPECT_EQ(notes, 1);
    EXPECT_EQ(ignored, 0);
}

TEST(AnimationPointer, APointerToWhatTheFileLacksIsRefusedNamingBoth) {
    auto refusal = [](const json& g) {
        try {
            loadJson(g, "bad");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("(loaded)");
    };
    EXPECT_NE(refusal(withPointers("/nodes/7/translation")).find("\"/nodes/7/translation\" names node 7, and the file has 2"),
              std::string::npos);
    json g = withPointers();
    g["animations"][0]["channels"].back()["target"]["extensions"]["KHR_animation_pointer"]["pointer"] = "/materials/3/emissiveFactor";
    EXPECT_NE(refusal(g).find("\"/materials/3/emissiveFactor\" names material 3, and the file has 1"), std::string::npos);
    g["animations"][0]["channels"].back()["target"]["extensions"] = json::object();
    EXPECT_NE(refusal(g).find("KHR_animation_pointer.pointer: missing"), std::string::npos);
}

}  // namespace rf::anim
