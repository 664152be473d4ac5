// The same model exported by Blender 3.4's own exporters as GLB, OBJ, STL, PLY and FBX
// (tests/reference/make_assimp_models.py; the files in tests/reference/assimp/) renders alike
// through the glTF loader and through assimp: a default still of each (framing, studio light,
// 4 spp) against the GLB's, scored by SSIM on the model's pixels (windows centred on a pixel
// either picture's camera ray meets the model) and by the coverage's intersection over union.
// A wrong up axis, unit, winding or material mapping moves or reshades the model and fails.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/util/file_source.h"
#include "engine/util/image.h"
#include "engine/util/image_metrics.h"
#include "engine/load/scene_loader.h"
#include "engine/integrators/render.h"
#include "anim/timeline.h"
#include "tests/engine/gltf_test_util.h"

using namespace rf;
namespace fs = std::filesystem;

namespace {

const std::string kData = std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/assimp/";
constexpr int kW = 192, kH = 108;

struct Still {
    std::vector<uint8_t> rgb;
    std::vector<uint8_t> mask;
    Camera camera;
};

/// The pose at frame `frame` of the default film (-1: the scene as loaded, no timeline).
Still still(const std::string& path, int frame = -1, const Camera* through = nullptr) {
    DiskFileSource files;
    SceneOptions opts;
    opts.width = kW;
    opts.height = kH;
    LoadedScene loaded = loadScene(path, files, opts);
    Scene& scene = loaded.scene;
    if (frame >= 0) anim::Timeline::fromScene(loaded).applyFrame(scene, frame);
    // Seen through another film's camera (the GLB's at that frame), so two films of different
    // lengths are compared at the same time from the same place.
    if (through) scene.camera = *through;
    RayStats stats;
    const Image img = renderFrame(scene, {scene.camera, scene.settings}, 0, 2, stats);
    Still s;
    s.camera = scene.camera;
    s.rgb = toRgb8(img, scene.settings);
    const CameraRays rays(scene.camera, kW, kH);
    s.mask.resize(size_t(kW) * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            Hit hit;
            s.mask[size_t(y) * kW + size_t(x)] = scene.geometry.intersect(rays.generate(float(x) + 0.5f, float(y) + 0.5f), hit) ? 1 : 0;
        }
    return s;
}

/// The binary STL written out as ASCII STL, so both readers see the same triangles.
std::string asciiStl(const std::string& binary) {
    std::string out = "solid suzanne\n";
    uint32_t n = 0;
    std::memcpy(&n, binary.data() + 80, 4);
    for (uint32_t i = 0; i < n; ++i) {
        float f[12];
        std::memcpy(f, binary.data() + 84 + size_t(i) * 50, sizeof f);
        char buf[512];
        std::snprintf(buf, sizeof buf,
                      "facet normal %.9g %.9g %.9g\n outer loop\n  vertex %.9g %.9g %.9g\n  vertex %.9g %.9g %.9g\n"
                      "  vertex %.9g %.9g %.9g\n endloop\nendfacet\n",
                      f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9], f[10], f[11]);
        out += buf;
    }
    return out + "endsolid suzanne\n";
}

}  // namespace

TEST(AssimpBlender, EveryFormatRendersLikeTheGlb) {
    const Still glb = still(kData + "suzanne.glb");
    gltftest::TempDir tmp;
    gltftest::writeFile(tmp / "suzanne_ascii.stl", asciiStl(gltftest::readFile(kData + "suzanne.stl")));
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/assimp-blender";
    fs::create_directories(out);
    writePng(out + "/suzanne.glb.png", kW, kH, glb.rgb);
    size_t glbCovered = 0;
    for (uint8_t m : glb.mask) glbCovered += m;
    ASSERT_GT(glbCovered, size_t(kW * kH / 20)) << "the GLB's model fills too little of the picture";
    for (const std::string& path : {kData + "suzanne.stl", tmp / "suzanne_ascii.stl", kData + "suzanne.ply", kData + "suzanne.obj",
                                    kData + "suzanne.fbx", kData + "suzanne_zup.fbx"}) {
        const Still s = still(path);
        std::vector<uint8_t> both(glb.mask.size());
        size_t inter = 0, uni = 0;
        for (size_t i = 0; i < both.size(); ++i) {
            both[i] = glb.mask[i] | s.mask[i];
            inter += glb.mask[i] & s.mask[i];
            uni += both[i];
        }
        const double iou = double(inter) / double(uni);
        const double ssim = ssimRgb8Masked(s.rgb, glb.rgb, kW, kH, both);
        const std::string name = fs::path(path).filename().string();
        std::printf("%-20s masked SSIM %.4f against the GLB, coverage IoU %.4f\n", name.c_str(), ssim, iou);
        // Geometry and one neutral material in every file: the same picture but for the
        // formats' own rounding (STL's millimetres and floats, FBX's centimetres).
        EXPECT_GE(ssim, 0.98) << name;
        EXPECT_GE(iou, 0.99) << name;
        if (!(ssim >= 0.98) || !(iou >= 0.99)) {
            writePng(out + "/" + name + ".png", kW, kH, s.rgb);
            writePng(out + "/" + name + ".diff.png", kW, kH, falseColorErrorRgb8(s.rgb, glb.rgb, kW, kH, 0.1));
        }
    }
}

/// Masked SSIM and coverage IoU of a against b.
std::pair<double, double> score(const Still& a, const Still& b) {
    std::vector<uint8_t> both(a.mask.size());
    size_t inter = 0, uni = 0;
    for (size_t i = 0; i < both.size(); ++i) {
        both[i] = a.mask[i] | b.mask[i];
        inter += a.mask[i] & b.mask[i];
        uni += both[i];
    }
    return {ssimRgb8Masked(a.rgb, b.rgb, kW, kH, both), double(inter) / double(uni)};
}

// Node animations of FBX and COLLADA play through the glTF timeline: Blender's export of a cone
// that moves and turns over 2 s above a box (make_assimp_models.py), as COLLADA and FBX against
// the GLB, at four frames of the default film (30 fps, the same times in every file), through the
// GLB film's camera at that frame. The pose is scored by the coverage's IoU
// (the materials differ: Blender writes no material to the GLB, a Phong one to COLLADA and FBX,
// so SSIM is printed, not held). COLLADA's clip is the GLB's (1/24 s to 49/24 s) and must match
// to 0.99. assimp starts FBX's keys at 0 s (a 2.000 s clip, not 2.042), so the FBX pose runs
// 1/24 s ahead of Blender's: 0.9 for FBX.
TEST(AssimpBlender, NodeAnimationsPlayLikeTheGlb) {
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/assimp-blender";
    fs::create_directories(out);
    for (int frame : {0, 15, 30, 45}) {
        const Still glb = still(kData + "animated.glb", frame);
        for (const char* name : {"animated.dae", "animated.fbx"}) {
            const Still s = still(kData + name, frame, &glb.camera);
            const auto [ssim, iou] = score(s, glb);
            const double need = std::string(name) == "animated.dae" ? 0.99 : 0.9;
            std::printf("%-14s frame %2d: coverage IoU %.4f against the GLB (masked SSIM %.4f)\n", name, frame, iou, ssim);
            EXPECT_GE(iou, need) << name << " frame " << frame;
            if (!(iou >= need)) {
                const std::string base = out + "/" + name + "." + std::to_string(frame);
                writePng(base + ".png", kW, kH, s.rgb);
                writePng(base + ".glb.png", kW, kH, glb.rgb);
                writePng(base + ".diff.png", kW, kH, falseColorErrorRgb8(s.rgb, glb.rgb, kW, kH, 0.1));
            }
        }
    }
    // And it moves: frame 30 (the cone up and right, turned) is not frame 0.
    const auto [ssim, iou] = score(still(kData + "animated.dae", 30), still(kData + "animated.dae", 0));
    EXPECT_LT(iou, 0.9) << "the COLLADA animation does not move the cone (SSIM " << ssim << ")";
}

// Skins of FBX and COLLADA pose as glTF skins do: Blender's export of a tube bound to a chain of
// three bones that bend and twist it over 2 s (make_assimp_models.py), as FBX and COLLADA against
// the GLB, at frames of the default film (30 fps; the keys start at 0 s in every file), through
// the GLB film's camera at that frame, scored by masked SSIM and the coverage's IoU. The same
// file drawn in its bind pose (as before skins were read: the scene as loaded, before any
// frame's pose) through the same camera must fail both thresholds at the bent frames, so a skin
// that is not posed shows.
TEST(AssimpBlender, SkinsPoseLikeTheGlb) {
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/assimp-blender";
    fs::create_directories(out);
    for (int frame : {15, 30, 45, 55}) {
        const Still glb = still(kData + "skinned.glb", frame);
        for (const char* name : {"skinned.fbx", "skinned.dae"}) {
            const Still s = still(kData + name, frame, &glb.camera);
            const Still rest = still(kData + name, -1, &glb.camera);
            const auto [ssim, iou] = score(s, glb);
            const auto [restSsim, restIou] = score(rest, glb);
            std::printf("%-12s frame %2d: masked SSIM %.4f, coverage IoU %.4f against the GLB; bind pose %.4f, %.4f\n", name, frame, ssim,
                        iou, restSsim, restIou);
            EXPECT_GE(ssim, 0.98) << name << " frame " << frame;
            EXPECT_GE(iou, 0.99) << name << " frame " << frame;
            EXPECT_TRUE(restSsim < 0.98 || restIou < 0.99) << name << " frame " << frame << ": the bind pose passes too";
            if (!(ssim >= 0.98) || !(iou >= 0.99)) {
                const std::string base = out + "/" + name + "." + std::to_string(frame);
                writePng(base + ".png", kW, kH, s.rgb);
                writePng(base + ".glb.png", kW, kH, glb.rgb);
                writePng(base + ".diff.png", kW, kH, falseColorErrorRgb8(s.rgb, glb.rgb, kW, kH, 0.1));
            }
        }
    }
}

// Morph targets of FBX (blend shapes) play as glTF's: Blender's sphere with two shape keys
// keyed over 2 s (make_assimp_models.py), as FBX against the GLB, at frames of the default film
// through the GLB film's camera, by masked SSIM and coverage IoU; the file at rest (the scene as
// loaded, every weight 0) through the same camera must fail them, so unplayed weights show.
// (Blender's COLLADA exporter writes no shape-key animation: COLLADA's morphs are not compared.)
TEST(AssimpBlender, MorphTargetsPlayLikeTheGlb) {
    const std::string out = std::string(RAYFARM_TEST_OUT) + "/assimp-blender";
    fs::create_directories(out);
    for (int frame : {10, 24, 36, 50}) {
        const Still glb = still(kData + "morph.glb", frame);
        const Still s = still(kData + "morph.fbx", frame, &glb.camera);
        const Still rest = still(kData + "morph.fbx", -1, &glb.camera);
        const auto [ssim, iou] = score(s, glb);
        const auto [restSsim, restIou] = score(rest, glb);
        std::printf("morph.fbx frame %2d: masked SSIM %.4f, coverage IoU %.4f against the GLB; at rest %.4f, %.4f\n", frame, ssim, iou,
                    restSsim, restIou);
        EXPECT_GE(ssim, 0.98) << "frame " << frame;
        EXPECT_GE(iou, 0.99) << "frame " << frame;
        EXPECT_TRUE(restSsim < 0.98 || restIou < 0.99) << "frame " << frame << ": the sphere at rest passes too";
        if (!(ssim >= 0.98) || !(iou >= 0.99)) {
            const std::string base = out + "/morph.fbx." + std::to_string(frame);
            writePng(base + ".png", kW, kH, s.rgb);
            writePng(base + ".glb.png", kW, kH, glb.rgb);
            writePng(base + ".diff.png", kW, kH, falseColorErrorRgb8(s.rgb, glb.rgb, kW, kH, 0.1));
        }
    }
}
