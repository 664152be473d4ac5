// Skinned characters against Blender Cycles, through the file's camera at two animation times:
// tests/reference/characters/ (make_characters.py: a walker of 13 bones with automatic weights
// and a walk cycle, and a car whose body and wheels are rigid parts skinned to three joints;
// references by cycles_reference.sh --time T --transparent, the commands in the README there).
// Scored as cycles_pose_score.h says: the coverage masks' IoU and SSIM on the model's pixels,
// and the other time's reference, which must fail.
#include <gtest/gtest.h>

#include <cstdio>

#include "anim/gltf_animation.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/load/scene_loader.h"
#include "tests/anim/cycles_pose_score.h"

using namespace rf;
using namespace rf::cyclestest;

namespace {

const std::string kDir = std::string(RAYFARM_SOURCE_DIR) + "/tests/reference/characters/";

/// `still MODEL --camera 0 --time t --background transparent --exposure 0 --tonemap clamp`,
/// with the file's first animation posed at t, at the reference's size.
Rgba renderAt(const std::string& name, double t, int w, int h) {
    DiskFileSource fs;
    LoadedScene sceneLoaded = loadScene(kDir + name + ".gltf", fs);
    Scene& scene = sceneLoaded.scene;
    const anim::GltfAnimationPlayer player(scene.geometry.models[0], 0, 0, true);
    player.apply(scene, t);
    useGltfCamera(scene, 0);
    return renderTransparent(scene, w, h);
}

/// Scores the render at time t against its reference (thresholds `want`), and against the
/// reference at `otherT`, which must fall below at least one of them.
void checkPose(const std::string& name, double t, double otherT, Score want) {
    char refName[64], otherName[64], base[64];
    std::snprintf(refName, sizeof refName, "%s.t%.2f.cycles.png", name.c_str(), t);
    std::snprintf(otherName, sizeof otherName, "%s.t%.2f.cycles.png", name.c_str(), otherT);
    std::snprintf(base, sizeof base, "%s.t%.2f", name.c_str(), t);
    const Rgba ref = readReference(kDir + refName), other = readReference(kDir + otherName);
    checkTime(name, renderAt(name, t, ref.w, ref.h), ref, other, t, otherT, want, "skinned_cycles", base);
}

}  // namespace

// Measured (2026-12-05): walker IoU 0.9940 and 0.9952, SSIM 0.9628 and 0.9676 (against the other
// time: IoU 0.444, SSIM 0.17); car IoU 0.9978, 0.9977, SSIM 0.9425, 0.9428 (other time: IoU 0.895,
// SSIM 0.52-0.54: the wheels have turned, the body bobs).
TEST(SkinnedCycles, WalkerMidStrideMatchesCycles) { checkPose("walker", 0.10, 0.60, {0.98, 0.94}); }
TEST(SkinnedCycles, WalkerOtherStrideMatchesCycles) { checkPose("walker", 0.60, 0.10, {0.98, 0.94}); }
TEST(SkinnedCycles, CarWithSkinnedWheelsMatchesCycles) { checkPose("car", 0.10, 0.35, {0.98, 0.92}); }
TEST(SkinnedCycles, CarWheelsTurnedMatchCycles) { checkPose("car", 0.35, 0.10, {0.98, 0.92}); }
