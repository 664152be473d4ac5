// Key tracks: the timeline cases 23, 24, 26, 27 and 28 of docs/stability.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include <glm/gtc/quaternion.hpp>

#include "anim/keyframes.h"

namespace rf::anim {
namespace {

DQuat aboutY(double deg) { return glm::angleAxis(glm::radians(deg), DVec3(0, 1, 0)); }
/// Rotation angle in degrees between two unit quaternions (sign-insensitive).
double angleBetweenDeg(const DQuat& a, const DQuat& b) {
    return glm::degrees(2.0 * std::acos(std::min(1.0, std::abs(glm::dot(a, b)))));
}
double qlen(const DQuat& q) { return std::sqrt(glm::dot(q, q)); }

KeyTrack rotationTrack(const DQuat& a, const DQuat& b, double t1 = 1.0) {
    KeyTrack t(4, true);
    const double va[4] = {a.x, a.y, a.z, a.w}, vb[4] = {b.x, b.y, b.z, b.w};
    t.addKey(0.0, va, Interp::Linear);
    t.addKey(t1, vb, Interp::Linear);
    return t;
}

// Case 23: a 21° pair stored with flipped sign must not become a 339° turn.
TEST(Slerp, SignFlippedNeighboursTakeTheShortPath) {
    const DQuat a = aboutY(0.0), b = -aboutY(21.0);
    const KeyTrack t = rotationTrack(a, b);
    for (double u : {0.25, 0.5, 0.75}) {
        const DQuat q = t.evaluateQuat(u);
        EXPECT_NEAR(angleBetweenDeg(q, a), 21.0 * u, 1e-9) << "u = " << u;
        EXPECT_NEAR(angleBetweenDeg(q, aboutY(21.0 * u)), 0.0, 1e-6);
    }
    // And the free function agrees: halfway is 10.5°, not 169.5°.
    EXPECT_NEAR(angleBetweenDeg(slerpShort(a, b, 0.5), a), 10.5, 1e-9);
}

// Case 24: dot ∈ {1, 1−1e-7, −1+1e-7, −1}: unit length, finite, continuous.
TEST(Slerp, NearParallelAndAntipodalStayUnitAndContinuous) {
    const DQuat a = aboutY(0.0);
    // cos(θ/2) = d gives these dot products exactly enough for the test's purpose.
    for (double d : {1.0, 1.0 - 1e-7, -1.0 + 1e-7, -1.0}) {
        const double half = std::acos(std::abs(d));
        DQuat b(std::cos(half), 0.0, std::sin(half), 0.0);
        if (d < 0) b = -b;
        ASSERT_NEAR(glm::dot(a, b), d, 1e-12);
        DQuat prev = slerpShort(a, b, 0.0);
        for (int i = 0; i <= 100; ++i) {
            const double u = i / 100.0;
            const DQuat q = slerpShort(a, b, u);
            ASSERT_TRUE(std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)) << d << " " << u;
            EXPECT_NEAR(qlen(q), 1.0, 1e-12) << d << " " << u;
            // Continuity: consecutive samples differ by at most the whole (tiny) arc / 100 + slack.
            EXPECT_LE(angleBetweenDeg(q, prev), glm::degrees(2 * half) / 100.0 + 1e-5) << d << " " << u;
            prev = q;
        }
        EXPECT_NEAR(angleBetweenDeg(slerpShort(a, b, 1.0), b), 0.0, 1e-6);
    }
}

// Case 26 with an explicit-tangent Hermite track: tangents are per second and scaled by the
// key interval (2 s), so v(0.5 s) = 4.0, not the unscaled 3.25.
TEST(Hermite, TangentsAreScaledByTheKeyInterval) {
    KeyTrack t(1, false);
    const double v0 = 0.0, v1 = 16.0, m = 8.0;
    t.addKey(0.0, &v0, Interp::Hermite, &m, &m);
    t.addKey(2.0, &v1, Interp::Hermite, &m, &m);
    EXPECT_DOUBLE_EQ(t.evaluateScalar(0.5), 4.0);
    // The same curve is the line 8·t (its tangents equal the chord slope).
    for (double x : {0.1, 0.9, 1.3, 1.99}) EXPECT_NEAR(t.evaluateScalar(x), 8.0 * x, 1e-12);
}

// Case 27: strictly increasing times.
TEST(KeyRules, EqualAndUnsortedTimesAreRejectedNamingTheKey) {
    for (double second : {1.0, 0.5}) {
        KeyTrack t(1, false);
        const double v = 1.0;
        t.addKey(0.0, &v, Interp::Linear);
        t.addKey(1.0, &v, Interp::Linear);
        try {
            t.addKey(second, &v, Interp::Linear);
            FAIL() << "time " << second << " after 1.0 was accepted";
        } catch (const KeyError& e) {
            EXPECT_EQ(e.key(), 2);
            EXPECT_EQ(e.field(), "time");
            EXPECT_NE(std::string(e.what()).find("increase"), std::string::npos);
        }
        EXPECT_EQ(t.size(), 2u);  // the bad key was not added
    }
    KeyTrack t(1, false);
    const double v = 1.0;
    EXPECT_THROW(t.addKey(std::nan(""), &v, Interp::Linear), KeyError);
    const double inf = INFINITY;
    EXPECT_THROW(t.addKey(0.0, &inf, Interp::Linear), KeyError);
}

// Case 27: clamping outside the range, bit-exact values at keys, STEP holds.
TEST(KeyRules, ClampsOutsideAndIsBitExactAtKeys) {
    // Awkward values and times so that any arithmetic at a key would show in the last bits.
    const double times[] = {0.1, 0.7, 1.3000000000000003, 2.9};
    const double values[] = {0.1 + 0.2, -1.0 / 3.0, 1e-17 + 1.0, 7.0 / 9.0};
    for (Interp how : {Interp::Step, Interp::Linear, Interp::Hermite, Interp::CatmullRom, Interp::EaseInOut}) {
        KeyTrack t(1, false);
        const double tan = 0.37;
        for (int k = 0; k < 4; ++k) t.addKey(times[k], &values[k], how, &tan, &tan);
        for (int k = 0; k < 4; ++k) {
            const double got = t.evaluateScalar(times[k]);
            EXPECT_EQ(std::memcmp(&got, &values[k], sizeof got), 0) << "interp " << int(how) << " key " << k;
        }
        EXPECT_EQ(t.evaluateScalar(-100.0), values[0]);
        EXPECT_EQ(t.evaluateScalar(0.0999), values[0]);
        EXPECT_EQ(t.evaluateScalar(2.90001), values[3]);
        EXPECT_EQ(t.evaluateScalar(1e300), values[3]);
        EXPECT_EQ(t.evaluateScalar(std::nan("")), values[0]);
    }
    KeyTrack step(3, false);
    const double a[3] = {1, 2, 3}, b[3] = {4, 5, 6};
    step.addKey(0.0, a, Interp::Step);
    step.addKey(1.0, b, Interp::Step);
    EXPECT_EQ(step.evaluateVec3(0.999999), DVec3(1, 2, 3));
    EXPECT_EQ(step.evaluateVec3(1.0), DVec3(4, 5, 6));
}

TEST(KeyRules, LinearAndEasingMeetTheirClosedForms) {
    KeyTrack lin(1, false), in(1, false), out(1, false), both(1, false);
    const double v0 = 2.0, v1 = 6.0;
    for (auto [t, how] : {std::pair{&lin, Interp::Linear}, {&in, Interp::EaseIn}, {&out, Interp::EaseOut}, {&both, Interp::EaseInOut}}) {
        t->addKey(1.0, &v0, how);
        t->addKey(3.0, &v1, how);
    }
    for (double u : {0.1, 0.25, 0.5, 0.8}) {
        const double x = 1.0 + 2.0 * u;
        EXPECT_NEAR(lin.evaluateScalar(x), 2.0 + 4.0 * u, 1e-12);
        EXPECT_NEAR(in.evaluateScalar(x), 2.0 + 4.0 * u * u, 1e-12);
        EXPECT_NEAR(out.evaluateScalar(x), 2.0 + 4.0 * (1 - (1 - u) * (1 - u)), 1e-12);
        EXPECT_NEAR(both.evaluateScalar(x), 2.0 + 4.0 * u * u * (3 - 2 * u), 1e-12);
    }
}

/// Barry–Goldman pyramid for the centripetal Catmull–Rom segment P1→P2 (Yuksel et al.'s
/// definition), evaluated independently of the Hermite form the track uses.
DVec3 barryGoldman(const DVec3 P[4], double u) {
    double k[4] = {0, 0, 0, 0};
    for (int i = 1; i < 4; ++i) k[i] = k[i - 1] + std::sqrt(glm::length(P[i] - P[i - 1]));
    const double t = k[1] + u * (k[2] - k[1]);
    auto lerp = [&](const DVec3& a, const DVec3& b, double ta, double tb) { return (tb - t) / (tb - ta) * a + (t - ta) / (tb - ta) * b; };
    const DVec3 A1 = lerp(P[0], P[1], k[0], k[1]), A2 = lerp(P[1], P[2], k[1], k[2]), A3 = lerp(P[2], P[3], k[2], k[3]);
    const DVec3 B1 = lerp(A1, A2, k[0], k[2]), B2 = lerp(A2, A3, k[1], k[3]);
    return lerp(B1, B2, k[1], k[2]);
}

// Case 28: the centripetal form, checked against the pyramid definition.
TEST(CatmullRom, MatchesTheCentripetalPyramid) {
    const DVec3 P[5] = {{0, 0, 0}, {1, 3, 0}, {1.2, 3.1, 0.5}, {5, -1, 2}, {6, 0, 0}};
    KeyTrack t(3, false);
    for (int k = 0; k < 5; ++k) t.addKey(double(k), &P[k].x, Interp::CatmullRom);
    for (int seg = 1; seg <= 2; ++seg)
        for (double u : {0.1, 0.33, 0.5, 0.77, 0.95}) {
            const DVec3 want = barryGoldman(&P[seg - 1], u);
            const DVec3 got = t.evaluateVec3(seg + u);
            EXPECT_NEAR(glm::length(got - want), 0.0, 1e-9) << "segment " << seg << " u " << u;
        }
}

// Case 28: duplicate points do not divide by zero.
TEST(CatmullRom, DuplicatePointsStayFiniteAndInterpolate) {
    const DVec3 P[6] = {{0, 0, 0}, {0, 0, 0}, {2, 1, 0}, {2, 1, 0}, {2, 1, 0}, {4, 0, 1}};
    KeyTrack t(3, false);
    for (int k = 0; k < 6; ++k) t.addKey(0.5 * k, &P[k].x, Interp::CatmullRom);
    for (int i = 0; i <= 250; ++i) {
        const double x = 0.01 * i;
        const DVec3 v = t.evaluateVec3(x);
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) << "t = " << x;
        // The curve stays near the keys' hull (no blow-up from a zero knot interval).
        EXPECT_GE(v.x, -0.5);
        EXPECT_LE(v.x, 4.5);
    }
    // Between two equal points the segment is constant.
    EXPECT_EQ(t.evaluateVec3(1.2), DVec3(2, 1, 0));
    // A duplicate neighbour gives, in the limit of the formula, a zero tangent at that end. On
    // 0.5 s..1 s both neighbours are duplicates, so the segment is P1 + (3u² − 2u³)(P2 − P1).
    for (double u : {0.25, 0.5, 0.8}) {
        const DVec3 want = P[1] + (3 * u * u - 2 * u * u * u) * (P[2] - P[1]);
        EXPECT_NEAR(glm::length(t.evaluateVec3(0.5 + 0.5 * u) - want), 0.0, 1e-12) << u;
    }
    // And a single-key or two-key track works too.
    KeyTrack two(1, false);
    const double a = 1.0, b = 3.0;
    two.addKey(0.0, &a, Interp::CatmullRom);
    two.addKey(1.0, &b, Interp::CatmullRom);
    EXPECT_NEAR(two.evaluateScalar(0.5), 2.0, 1e-12);  // mirrored ends: a straight line
}

TEST(KeyRules, RotationKeysAreNormalisedAndZeroIsRejected) {
    KeyTrack t(4, true);
    const double q[4] = {0, 0, 0, 2};
    t.addKey(0.0, q, Interp::Linear);
    EXPECT_EQ(t.evaluateQuat(0.0), DQuat(1, 0, 0, 0));
    const double z[4] = {0, 0, 0, 0};
    EXPECT_THROW(t.addKey(1.0, z, Interp::Linear), KeyError);
}

}  // namespace
}  // namespace rf::anim
