#include "farm/view/orbit_camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rf::view {
namespace {

Camera testCamera() {
    Camera c;
    c.eye = Vec3(1.f, 2.f, 6.f);
    c.target = Vec3(0.5f, 1.f, 0.f);
    c.fovDeg = 40.f;
    return c;
}

double dist(const Camera& c) { return glm::length(DVec3(c.eye) - DVec3(c.target)); }

TEST(OrbitCamera, OrbitKeepsTargetAndDistance) {
    const Camera c = testCamera();
    const Camera o = orbit(c, 37.0, -12.0);
    EXPECT_EQ(o.target, c.target);
    EXPECT_NEAR(dist(o), dist(c), 1e-5 * dist(c));
    EXPECT_GT(glm::length(o.eye - c.eye), 0.1f);
}

TEST(OrbitCamera, OrbitNeverCrossesThePole) {
    const Camera c = testCamera();
    for (double dy : {1e4, -1e4}) {
        const Camera o = orbit(c, 0.0, dy);
        const DVec3 view = glm::normalize(DVec3(o.eye) - DVec3(o.target));
        // 0.02 rad from the up axis at least: the view direction never lines up with up.
        EXPECT_LT(std::abs(view.y), std::cos(0.019)) << dy;
    }
}

TEST(OrbitCamera, HorizontalDragTurnsAboutTheUpAxis) {
    const Camera c = testCamera();
    const Camera o = orbit(c, 50.0, 0.0);
    EXPECT_NEAR(o.eye.y, c.eye.y, 1e-5);  // height above the target kept
}

TEST(OrbitCamera, PanMovesEyeAndTargetTogether) {
    const Camera c = testCamera();
    const Camera p = pan(c, 20.0, 10.0, 100);
    const Vec3 de = p.eye - c.eye, dt = p.target - c.target;
    EXPECT_NEAR(glm::length(de - dt), 0.f, 1e-5f);
    EXPECT_GT(glm::length(de), 0.f);
    // 100 pixels span 2·d·tan(20°) vertically: 20 and 10 pixels move sqrt(500)/100 of that.
    const double expected = std::sqrt(500.0) / 100.0 * 2.0 * dist(c) * std::tan(glm::radians(20.0));
    EXPECT_NEAR(glm::length(DVec3(de)), expected, 1e-4 * expected);
}

TEST(OrbitCamera, ZoomStepIsTenPercentOfTheDistance) {
    const Camera c = testCamera();
    EXPECT_NEAR(dist(zoom(c, 1.0)), 0.9 * dist(c), 1e-5 * dist(c));
    EXPECT_NEAR(dist(zoom(c, -2.0)), dist(c) / 0.81, 1e-5 * dist(c));
}

TEST(OrbitCamera, FrameBoxFitsTheBoundingSphere) {
    Camera c = testCamera();
    Aabb box;
    box.grow(Vec3(-3.f, 0.f, -1.f));
    box.grow(Vec3(5.f, 2.f, 1.f));
    const double aspect = 16.0 / 9.0;
    const Camera f = frameBox(c, box, aspect);
    const DVec3 center(1.0, 1.0, 0.0);
    EXPECT_NEAR(glm::length(DVec3(f.target) - center), 0.0, 1e-6);
    const double radius = 0.5 * glm::length(DVec3(8.0, 2.0, 2.0));
    // Vertical fov is the narrower one at 16:9: the sphere subtends at most its half angle.
    const double half = std::asin(radius / dist(f));
    EXPECT_LT(half, glm::radians(20.0));
    EXPECT_GT(half, glm::radians(20.0) / 1.2);  // and fills most of it
    // The view direction is kept.
    const DVec3 d0 = glm::normalize(DVec3(c.eye) - DVec3(c.target)), d1 = glm::normalize(DVec3(f.eye) - DVec3(f.target));
    EXPECT_NEAR(glm::dot(d0, d1), 1.0, 1e-6);
}

}  // namespace
}  // namespace rf::view
