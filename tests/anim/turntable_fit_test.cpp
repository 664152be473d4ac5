// The silhouette fit of anim/turntable_fit.*: exact for the points it is given (the worst frame
// touches the margin, no frame passes it), its reduced point set holds every vertex, and the
// look-at point rises to centre a model whose mass sits high.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "anim/turntable.h"
#include "anim/turntable_fit.h"

namespace rf::anim {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Largest |x|/(z·tanX) or |y|/(z·tanY) of any point in any frame of the fitted orbit, with
/// the camera basis built by the engine's lookAt (as the renderer builds it).
double worstReach(const std::vector<DVec3>& pts, const OrbitView& v, const OrbitFit& fit, bool& behind) {
    double worst = 0.0;
    behind = false;
    const DVec3 target(0.0, fit.lift, 0.0);
    for (double yaw : v.yaws) {
        const OrbitPose pose = orbitPose(yaw, v.elevation);
        const DVec3 eye = target + fit.distance * pose.toEye;
        const CameraBasis b = lookAt(Vec3(eye), Vec3(target), Vec3(pose.up));
        for (const DVec3& p : pts) {
            const DVec3 r = p - eye;
            const double z = glm::dot(r, DVec3(b.forward));
            behind |= z <= 0.0;
            worst = std::max({worst, std::abs(glm::dot(r, DVec3(b.right))) / (z * v.tanX),
                              std::abs(glm::dot(r, DVec3(b.up))) / (z * v.tanY)});
        }
    }
    return worst;
}

std::vector<DVec3> randomCloud(int n, DVec3 scale, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<DVec3> pts;
    for (int i = 0; i < n; ++i) pts.emplace_back(u(rng) * scale.x, u(rng) * scale.y, u(rng) * scale.z);
    return pts;
}

OrbitView orbit(int frames, double elevationDeg, double tanY, double aspect) {
    OrbitView v;
    for (int i = 0; i < frames; ++i) v.yaws.push_back(2.0 * kPi * i / frames);
    v.elevation = elevationDeg * kPi / 180.0;
    v.tanY = tanY;
    v.tanX = tanY * aspect;
    return v;
}

TEST(OrbitFit, WorstFrameTouchesTheMarginAndNoFramePassesIt) {
    for (double elevation : {0.0, 20.0, -35.0, 70.0}) {
        for (const DVec3 scale : {DVec3(3, 0.2, 1), DVec3(0.3, 2, 0.3), DVec3(1, 1, 1)}) {
            const std::vector<DVec3> pts = randomCloud(300, scale, 7);
            const OrbitView v = orbit(60, elevation, std::tan(kPi / 9.0), 16.0 / 9.0);
            const OrbitFit fit = fitOrbit(pts, v, 0.9, 10.0);
            ASSERT_GT(fit.distance, 0.0);
            bool behind = false;
            const double reach = worstReach(pts, v, fit, behind);
            EXPECT_FALSE(behind);
            EXPECT_NEAR(reach, 0.9, 1e-6) << "elevation " << elevation << ", scale " << scale.x << " " << scale.y;
        }
    }
}

TEST(OrbitFit, LiftCentresAModelThatSitsOffTheOrbitCentre) {
    // A thin post down to y = −2 under a wide plate at y ≈ 1: seen level through a wide frame,
    // height binds, and the centred look-at point sinks towards the middle of the extent.
    std::vector<DVec3> pts = {{0, -2, 0}, {0.05, -2, 0.05}};
    for (int i = 0; i < 32; ++i) {
        const double a = 2.0 * kPi * i / 32;
        pts.emplace_back(0.6 * std::cos(a), 1.0, 0.6 * std::sin(a));
        pts.emplace_back(0.6 * std::cos(a), 1.2, 0.6 * std::sin(a));
    }
    const OrbitView v = orbit(8, 0.0, std::tan(kPi / 9.0), 2.0);
    const OrbitFit fit = fitOrbit(pts, v, 0.9, 2.0);
    EXPECT_LT(fit.lift, -0.2);
    EXPECT_GT(fit.lift, -0.6);
    // Centred: the top and the bottom reach the same share of the half-height.
    double up = 0.0, down = 0.0;
    const DVec3 target(0.0, fit.lift, 0.0);
    for (double yaw : v.yaws) {
        const OrbitPose pose = orbitPose(yaw, v.elevation);
        const DVec3 eye = target + fit.distance * pose.toEye;
        for (const DVec3& p : pts) {
            const double z = glm::dot(p - eye, -pose.toEye), y = p.y - fit.lift;
            up = std::max(up, y / (z * v.tanY));
            down = std::max(down, -y / (z * v.tanY));
        }
    }
    EXPECT_NEAR(up, 0.9, 1e-6);
    EXPECT_NEAR(down, 0.9, 1e-6);
    // With the lift held at 0 the same margin needs a longer distance.
    EXPECT_GT(fitOrbit(pts, v, 0.9, 0.0).distance, fit.distance * 1.05);
}

TEST(SilhouettePoints, HullHoldsEveryVertexInEveryDirection) {
    Scene s;
    TriangleMesh m;
    std::mt19937 rng(3);
    std::normal_distribution<float> g(0.f, 1.f);
    for (int i = 0; i < 20000; ++i) m.positions.push_back(Vec3(2.f * g(rng), 0.5f * g(rng) + 1.f, g(rng)));
    s.geometry.meshes.push_back(m);
    const DVec3 c(0.3, 1.0, -0.2);
    const std::vector<DVec3> hull = silhouettePoints(s, c);
    EXPECT_LE(hull.size(), 8320u);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    double worstGrowth = 1.0;
    for (int k = 0; k < 500; ++k) {
        const DVec3 d = glm::normalize(DVec3(u(rng), u(rng), u(rng)));
        double vMax = -1e300, hMax = -1e300;
        for (const Vec3& p : m.positions) vMax = std::max(vMax, glm::dot(DVec3(p) - c, d));
        for (const DVec3& p : hull) hMax = std::max(hMax, glm::dot(p, d));
        EXPECT_GE(hMax, vMax - 1e-9) << "a vertex lies outside the reduced hull";
        worstGrowth = std::max(worstGrowth, hMax / vMax);
    }
    // Conservative but tight: the support grows by a bin's size at most.
    EXPECT_LT(worstGrowth, 1.1);
}

TEST(Turntable, SilhouetteFitFramesCloserThanTheSphere) {
    Scene s;  // a long thin bar: its sphere is far larger than what any view shows of it
    TriangleMesh m;
    m.positions = {Vec3(-4, -0.2f, -0.2f), Vec3(4, 0.2f, 0.2f), Vec3(4, -0.2f, 0.2f)};
    s.geometry.meshes.push_back(m);
    s.camera.fovDeg = 40.f;
    TurntableSettings ts;
    const double sphere = Turntable::framed(ts, s).distance();
    ts.fitSilhouette = true;
    const Turntable fit = Turntable::framed(ts, s);
    EXPECT_LT(fit.distance(), 0.8 * sphere);
    // A distance the user gave wins over either fit.
    ts.distance = 3.0;
    EXPECT_EQ(Turntable::framed(ts, s).distance(), 3.0);
}

}  // namespace
}  // namespace rf::anim
