// Camera: look-at degenerate cases (catalogue 29), field of view along either axis, aspect
// ratio and the left-handed (POV-Ray) image axis.
#include <gtest/gtest.h>

#include "engine/geometry/camera.h"

using namespace rf;

namespace {
void expectOrthonormal(const CameraBasis& b) {
    EXPECT_TRUE(isFinite(b.right) && isFinite(b.up) && isFinite(b.forward));
    EXPECT_NEAR(glm::length(b.right), 1.f, 1e-6f);
    EXPECT_NEAR(glm::length(b.up), 1.f, 1e-6f);
    EXPECT_NEAR(glm::length(b.forward), 1.f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.right, b.up), 0.f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.right, b.forward), 0.f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.up, b.forward), 0.f, 1e-6f);
    // Right-handed: right × up = −forward (the camera looks down its −z).
    const float det = glm::dot(glm::cross(b.right, b.up), -b.forward);
    EXPECT_NEAR(det, 1.f, 1e-5f);
}
}  // namespace

TEST(Camera, LookAtOrdinaryCase) {
    const CameraBasis b = lookAt(Vec3(0, 0, 5), Vec3(0.f), Vec3(0, 1, 0));
    expectOrthonormal(b);
    EXPECT_NEAR(b.forward.z, -1.f, 1e-6f);
    EXPECT_NEAR(b.up.y, 1.f, 1e-6f);
    EXPECT_NEAR(b.right.x, 1.f, 1e-6f);
}

TEST(Camera, LookAtForwardParallelToUpStaysOrthonormal) {
    for (const Vec3& target : {Vec3(0, -10, 0), Vec3(0, 10, 0), Vec3(0, 1e-3f, 0)}) {
        const CameraBasis b = lookAt(Vec3(0.f), target, Vec3(0, 1, 0));
        expectOrthonormal(b);
        EXPECT_NEAR(std::abs(b.forward.y), 1.f, 1e-6f);
    }
    // Nearly parallel, and a zero up vector.
    expectOrthonormal(lookAt(Vec3(0.f), Vec3(1e-9f, -1.f, 0.f), Vec3(0, 1, 0)));
    expectOrthonormal(lookAt(Vec3(0.f), Vec3(1, 2, 3), Vec3(0.f)));
}

TEST(Camera, LookAtEyeEqualsTargetFallsBackWithoutNaN) {
    const CameraBasis b = lookAt(Vec3(3, 4, 5), Vec3(3, 4, 5), Vec3(0, 1, 0));
    expectOrthonormal(b);
}

TEST(Camera, VerticalAndHorizontalFieldOfView) {
    Camera cam;
    cam.eye = Vec3(0.f);
    cam.target = Vec3(0, 0, -1);
    cam.fovDeg = 90.f;
    const CameraRays v(cam, 200, 100);
    // Top edge centre: 45° above the axis; right edge centre: atan(2·tan 45°) to the side.
    const Ray top = v.generate(100.f, 0.f);
    EXPECT_NEAR(std::atan2(top.d.y, -top.d.z), glm::radians(45.f), 1e-5f);
    const Ray right = v.generate(200.f, 50.f);
    EXPECT_NEAR(std::atan2(right.d.x, -right.d.z), std::atan(2.f), 1e-5f);
    cam.fovHorizontal = true;
    const CameraRays h(cam, 200, 100);
    EXPECT_NEAR(std::atan2(h.generate(200.f, 50.f).d.x, -h.generate(200.f, 50.f).d.z), glm::radians(45.f), 1e-5f);
    EXPECT_NEAR(std::atan2(h.generate(100.f, 0.f).d.y, -h.generate(100.f, 0.f).d.z), std::atan(0.5f), 1e-5f);
    // Centre ray straight ahead, unit length.
    const Ray c = h.generate(100.f, 50.f);
    EXPECT_NEAR(c.d.z, -1.f, 1e-6f);
    EXPECT_NEAR(glm::length(c.d), 1.f, 1e-6f);
}

TEST(Camera, LeftHandedMirrorsTheImageXAxis) {
    Camera cam;
    cam.eye = Vec3(0, 0, -8);
    cam.target = Vec3(0.f);
    const CameraRays rh(cam, 64, 64);
    cam.leftHanded = true;
    const CameraRays lh(cam, 64, 64);
    // Looking down +z with y up: right-handed puts −x on the image's right, POV-Ray puts +x.
    EXPECT_LT(rh.generate(60.f, 32.f).d.x, 0.f);
    EXPECT_GT(lh.generate(60.f, 32.f).d.x, 0.f);
    EXPECT_EQ(lh.generate(60.f, 10.f).d.y, rh.generate(60.f, 10.f).d.y);
}
