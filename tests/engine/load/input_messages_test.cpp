// Issue 30 #9: messages that name the real cause, on one line, whatever the file holds. Keys
// and names from a file reach the terminal escaped (a NUL no longer cuts the message short, a
// newline or an escape sequence no longer reaches the terminal raw); a GLB with an empty JSON
// chunk says so; a camera whose yfov is 0 is refused when chosen instead of becoming 45°.
#include <gtest/gtest.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_loader.h"
#include "tests/engine/gltf_test_util.h"
#include "engine/load/scene_loader.h"

using namespace rf;
using namespace gltftest;

namespace {

float kA[3] = {0, 0, 0}, kB[3] = {1, 0, 0}, kC[3] = {0, 1, 0};

/// The InputError loading `path` throws ("" if it loads).
std::string loadError(const std::string& path, Scene* out = nullptr) {
    DiskFileSource fs;
    try {
        LoadedScene sLoaded = loadScene(path, fs);
        Scene& s = sLoaded.scene;
        if (out) *out = std::move(s);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

bool hasControlCharacter(const std::string& s) {
    for (unsigned char c : s)
        if (c < 0x20 || c == 0x7f) return true;
    return false;
}

}  // namespace

TEST(InputMessages, PrintableEscapesControlCharactersOnly) {
    EXPECT_EQ(printable("plain name.gltf"), "plain name.gltf");
    EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\u0000b");
    EXPECT_EQ(printable("line\nbreak\r\ttab"), "line\\nbreak\\r\\ttab");
    EXPECT_EQ(printable("\x1b[2J\x7f"), "\\u001b[2J\\u007f");
    EXPECT_EQ(printable("caf\xc3\xa9 \xe2\x9c\x93 \xf0\x9f\x8e\xa5"), "caf\xc3\xa9 \xe2\x9c\x93 \xf0\x9f\x8e\xa5");  // UTF-8 kept
    EXPECT_EQ(printable("\xc2\x9b" "31m"), "\\u009b31m");  // C1 CSI, as UTF-8
    EXPECT_EQ(printable("\x9b\xff\xc3"), "\\x9b\\xff\\xc3");  // not UTF-8
    EXPECT_EQ(printable("back\\slash"), "back\\slash");
    EXPECT_EQ(printable(printable("a\nb")), printable("a\nb"));  // escaping twice changes nothing
}

// "ab\u0000cd" as a key: what() used to end at the NUL, so the message lost the key's end and
// everything after it.
TEST(InputMessages, AKeyHoldingNulIsPrintedWhole) {
    TempDir dir;
    writeFile(dir / "s.json", R"({"camera": {"eye": [0, 0, 5]}, "ab\u0000cd": 1})");
    const std::string e = loadError(dir / "s.json");
    EXPECT_NE(e.find("ab\\u0000cd"), std::string::npos) << e;
    EXPECT_GT(e.size(), e.find("ab\\u0000cd") + 12) << e;  // the rest of the message follows the key
    EXPECT_EQ(e.find('\0'), std::string::npos);
}

TEST(InputMessages, KeysWithNewlinesOrEscapeSequencesAreEscaped) {
    TempDir dir;
    writeFile(dir / "s.json", R"({"materials": {"red\n\u001b[31mred": {"color": [1, 0]}}})");
    const std::string e = loadError(dir / "s.json");
    ASSERT_FALSE(e.empty());
    EXPECT_NE(e.find("materials.red\\n\\u001b[31mred"), std::string::npos) << e;
    EXPECT_FALSE(hasControlCharacter(e)) << e;
    // A file name with a newline, too.
    writeFile(dir / "two\nlines.json", R"({"nonsense": 1})");
    const std::string f = loadError(dir / "two\nlines.json");
    EXPECT_NE(f.find("two\\nlines.json: "), std::string::npos) << f;
    EXPECT_FALSE(hasControlCharacter(f)) << f;
}

// The JSON chunk's length 0 made the loader read the JSON's bytes as the BIN chunk's header.
TEST(InputMessages, AGlbWithAnEmptyJsonChunkSaysSo) {
    TempDir dir;
    const std::string js = oneTriangleGltf(dataUri(oneTriangleBytes(kA, kB, kC))).dump();
    std::string glb = "glTF";
    put<uint32_t>(glb, {2u, uint32_t(20 + js.size()), 0u, 0x4E4F534Au});
    glb += js;
    writeFile(dir / "empty.glb", glb);
    EXPECT_EQ(loadError(dir / "empty.glb"), dir / "empty.glb" + ": GLB JSON chunk is empty (its length is 0)");
}

// yfov 0 became 45° without a word. The camera is refused when chosen; a model whose camera is
// never chosen still loads.
TEST(InputMessages, ACameraWithoutAFieldOfViewIsRefusedWhenChosen) {
    TempDir dir;
    writeFile(dir / "tri.bin", oneTriangleBytes(kA, kB, kC));
    json doc = oneTriangleGltf("tri.bin");
    doc["nodes"].push_back({{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}});
    doc["nodes"].push_back({{"camera", 1}, {"translation", {0.0, 0.0, 4.0}}});
    doc["scenes"][0]["nodes"] = {0, 1, 2};
    doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.0}, {"znear", 0.1}}}},
                      {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    writeFile(dir / "cams.gltf", doc.dump());
    Scene s;
    ASSERT_EQ(loadError(dir / "cams.gltf", &s), "");
    ASSERT_EQ(s.gltfCameras.size(), 2u);
    try {
        useGltfCamera(s, 0);
        ADD_FAILURE() << "a camera with yfov 0 was used";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), dir / "cams.gltf" +
                                             ": cameras[0].perspective.yfov 0 is not a field of view (expected radians between 0 "
                                             "and pi); choose another --camera");
    }
    useGltfCamera(s, 1);
    EXPECT_NEAR(s.camera.fovDeg, 0.5f * 180.f / 3.14159265f, 1e-4f);
}
