// Turntables and frame times: the timeline cases 25, 29 and 30 of docs/stability.md.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "engine/geometry/camera.h"
#include "anim/frame_time.h"
#include "anim/timeline.h"
#include "anim/turntable.h"

namespace rf::anim {
namespace {

Scene twoSpheres() {
    Scene s;
    s.geometry.spheres.push_back(Sphere{});
    s.geometry.spheres.back().center = Vec3(-1.f, 0.f, 0.f);
    s.geometry.spheres.back().radius = 1.f;
    s.geometry.spheres.push_back(Sphere{});
    s.geometry.spheres.back().center = Vec3(3.f, 0.f, 0.f);
    s.geometry.spheres.back().radius = 1.f;
    s.camera.fovDeg = 40.f;
    s.settings.width = 200;
    s.settings.height = 100;
    return s;
}

double det(const CameraBasis& b) { return glm::dot(b.right, glm::cross(b.up, b.forward)); }

void expectOrthonormal(const CameraBasis& b) {
    for (const Vec3& v : {b.right, b.up, b.forward}) {
        ASSERT_TRUE(isFinite(v));
        EXPECT_NEAR(glm::length(v), 1.0, 1e-5);
    }
    EXPECT_NEAR(glm::dot(b.right, b.up), 0.0, 1e-5);
    EXPECT_NEAR(glm::dot(b.right, b.forward), 0.0, 1e-5);
    EXPECT_NEAR(glm::dot(b.up, b.forward), 0.0, 1e-5);
    EXPECT_NEAR(std::abs(det(b)), 1.0, 1e-5);
}

// Case 25: yaw = 2π·f/N; at frame N/4 it is 90°, and the loop closes without a duplicate.
TEST(Turntable, YawIsTwoPiFOverNAndQuarterLoopIsNinetyDegrees) {
    Scene s = twoSpheres();
    TurntableSettings ts;
    ts.seconds = 4.0;
    ts.fps = 30.0;
    ts.elevationDeg = 0.0;
    const Turntable t = Turntable::framed(ts, s);
    const int n = t.frameCount();
    ASSERT_EQ(n, 120);
    EXPECT_NEAR(glm::degrees(t.yawAtFrame(n / 4)), 90.0, 1e-12);
    EXPECT_NEAR(glm::degrees(t.yawAt(frameTime(0.0, 30.0, n / 4))), 90.0, 1e-12);
    // The frame after the last would be frame 0 again; the last is one step short of 360°.
    EXPECT_NEAR(glm::degrees(t.yawAtFrame(n - 1)), 360.0 - 3.0, 1e-12);
    // The camera at N/4 sits on +x of the centre (frame 0 is on +z), at the framing distance.
    t.apply(s, frameTime(0.0, 30.0, n / 4), s.lights);
    const DVec3 off = DVec3(s.camera.eye) - t.centerRender();
    EXPECT_NEAR(off.x, t.distance(), 1e-4 * t.distance());
    EXPECT_NEAR(off.z, 0.0, 1e-4 * t.distance());
    EXPECT_EQ(s.camera.target, Vec3(t.centerRender()));
}

TEST(Turntable, AutoDistanceFitsTheBoundingSphere) {
    Scene s = twoSpheres();  // bounds x ∈ [−2, 4], y, z ∈ [−1, 1]: centre (1, 0, 0)
    const Turntable t = Turntable::framed(TurntableSettings{}, s);
    EXPECT_NEAR(glm::length(t.centerRender() - DVec3(1, 0, 0)), 0.0, 1e-6);
    const double radius = 0.5 * std::sqrt(36.0 + 4.0 + 4.0);
    // Vertical fov 40° is the narrower one at 2:1; the sphere fits with a 10 % margin.
    EXPECT_NEAR(t.distance(), 1.1 * radius / std::sin(glm::radians(20.0)), 1e-4);
}

TEST(Turntable, FollowingLightsTurnWithTheCameraFixedOnesStay) {
    Scene s = twoSpheres();
    Light l;
    l.position = Vec3(1.f, 5.f, 4.f);  // (0, 5, 4) from the centre
    s.lights.push_back(l);
    const std::vector<Light> rest = s.lights;
    TurntableSettings ts;
    ts.lightsFollow = true;
    const Turntable follow = Turntable::framed(ts, s);
    follow.apply(s, 1.0, rest);  // frame 30 of 120: a quarter turn
    EXPECT_NEAR(s.lights[0].position.x, 1.f + 4.f, 1e-5);
    EXPECT_NEAR(s.lights[0].position.y, 5.f, 1e-5);
    EXPECT_NEAR(s.lights[0].position.z, 0.f, 1e-5);
    follow.apply(s, 0.0, rest);  // absolute: back at frame 0, back at rest
    EXPECT_NEAR(glm::length(s.lights[0].position - rest[0].position), 0.f, 1e-5);
    ts.lightsFollow = false;
    Turntable::framed(ts, s).apply(s, 1.0, rest);
    EXPECT_EQ(s.lights[0].position, rest[0].position);
}

// Case 29: the pole of a look-at orbit (forward parallel to up) keeps an orthonormal basis,
// and the view still turns with the yaw there.
TEST(Turntable, PoleOfTheOrbitGivesAnOrthonormalTurningBasis) {
    for (double elevation : {90.0, -90.0, 89.9999999}) {
        Scene s = twoSpheres();
        TurntableSettings ts;
        ts.elevationDeg = elevation;
        const Turntable t = Turntable::framed(ts, s);
        CameraBasis prev;
        for (int f : {0, 30, 60}) {
            t.apply(s, frameTime(0.0, 30.0, f), s.lights);
            const CameraBasis b = lookAt(s.camera.eye, s.camera.target, s.camera.up);
            expectOrthonormal(b);
            if (f > 0) {
                EXPECT_LT(glm::dot(b.right, prev.right), 0.1f) << "the picture did not turn at the pole";
            }
            prev = b;
        }
    }
}

// Case 29 for the engine's lookAt as the timeline drives it: eye == target, up ∥ forward.
TEST(LookAt, DegenerateInputsStillGiveAnOrthonormalBasis) {
    expectOrthonormal(lookAt(Vec3(1, 2, 3), Vec3(1, 2, 3), Vec3(0, 1, 0)));
    expectOrthonormal(lookAt(Vec3(0, 5, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)));
    expectOrthonormal(lookAt(Vec3(0, -5, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)));
    expectOrthonormal(lookAt(Vec3(0, 0, 0), Vec3(1e-30f, 1, 0), Vec3(0, 1, 0)));
}

// Case 30: frame times from the index, never accumulated.
TEST(FrameTime, Frame100000At30FpsIsExact) {
    EXPECT_EQ(frameTime(0.0, 30.0, 100000), 3333.3333333333333);
    double acc = 0.0;
    for (int i = 0; i < 100000; ++i) acc += 1.0 / 30.0;
    // Why it matters: the accumulated sum drifts away from the exact time.
    EXPECT_NE(acc, 3333.3333333333333);
    // Through a timeline too: a 30 fps film long enough to have frame 100000.
    Scene s;
    s.sourcePath = "long.json";
    TimelineSource source;
    source.sections = std::make_shared<const nlohmann::json>(nlohmann::json::parse(R"({"timeline": {"fps": 30, "duration": 4000, "start": 0}})"));
    const Timeline tl = Timeline::fromScene(s, source);
    ASSERT_GT(tl.frameCount(), 100000);
    EXPECT_EQ(tl.frameTime(100000), 3333.3333333333333);
    EXPECT_EQ(tl.frameTime(100000), 100000.0 / 30.0);
}

TEST(FrameTime, CountsLoopsWithoutTheRepeatedFrame) {
    EXPECT_EQ(frameCount(4.0, 30.0), 120);
    EXPECT_EQ(frameCount(0.0, 30.0), 1);
    EXPECT_EQ(frameCount(1.0 / 3.0, 30.0), 10);
}

}  // namespace
}  // namespace rf::anim
