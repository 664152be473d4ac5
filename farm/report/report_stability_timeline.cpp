// Timeline cases of `rayfarm report --stability` (catalogue #23–#30), measured through anim/'s
// key tracks and turntable and the engine's lookAt.
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/geometry/camera.h"
#include "anim/frame_time.h"
#include "anim/keyframes.h"
#include "farm/report/report_stability.h"
#include "anim/turntable.h"

namespace rf::report {

using stability::formatValue;

namespace {

constexpr double kPi = 3.14159265358979323846;

StabilityCase check(const std::string& id, const std::string& name, const std::string& measured, double error,
                    double tolerance, const std::string& unit) {
    StabilityCase c{id, name, measured, error, tolerance, unit, false, false};
    c.pass = std::isfinite(error) && error <= tolerance;
    return c;
}

/// Angle of the rotation q, in degrees (0..180).
double angleDeg(const DQuat& q) {
    // atan2 rather than acos(w): acos loses half the digits for the tiny angles tested here.
    return 2.0 * std::atan2(glm::length(DVec3(q.x, q.y, q.z)), std::abs(q.w)) * 180.0 / kPi;
}

void shortPath(std::vector<StabilityCase>& out) {
    // 21° about y, stored with the sign flipped: the same rotation; half way must be 10.5°.
    const double h = 10.5 * kPi / 180.0;
    anim::KeyTrack track(4, true);
    const double q0[4] = {0, 0, 0, 1};
    const double q1[4] = {0, -std::sin(h), 0, -std::cos(h)};
    track.addKey(0.0, q0, anim::Interp::Linear);
    track.addKey(1.0, q1, anim::Interp::Linear);
    const double a = angleDeg(track.evaluateQuat(0.5));
    out.push_back(check("23", "21° key pair stored sign-flipped, half way", formatValue("%.6f° turned (short path: 10.5°)", a),
                        std::abs(a - 10.5), 1e-9, "degrees"));
}

void slerpEdges(std::vector<StabilityCase>& out) {
    // Pairs with a·b ∈ {1, 1−1e-7, −1+1e-7, −1}: b is a rotated by the matching small angle
    // (negated for the −1 cases).
    const DQuat a = glm::normalize(DQuat(0.8, 0.2, -0.3, 0.4));
    double worstNorm = 0.0, worstTurn = 0.0;
    bool finite = true;
    for (double dot : {1.0, 1.0 - 1e-7, -1.0 + 1e-7, -1.0}) {
        const double theta = std::acos(std::min(1.0, std::abs(dot)));  // angle between a and ±b
        const DQuat turn = glm::angleAxis(2.0 * theta, glm::normalize(DVec3(0.3, 1.0, -0.2)));
        DQuat b = turn * a;
        if (dot < 0) b = -b;
        const double full = angleDeg(glm::conjugate(a) * b);
        for (double u : {0.0, 0.25, 0.5, 0.75, 1.0}) {
            const DQuat q = anim::slerpShort(a, b, u);
            finite &= std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) && std::isfinite(q.w);
            worstNorm = std::max(worstNorm, std::abs(glm::length(q) - 1.0));
            // Continuous and on the short path: the turn from a grows linearly to the full turn.
            worstTurn = std::max(worstTurn, std::abs(angleDeg(glm::conjugate(a) * q) - u * full));
        }
    }
    out.push_back(check("24", "slerp at a·b = 1, 1−1e-7, −1+1e-7, −1",
                        formatValue("worst norm error %.2g", worstNorm) + formatValue(", worst turn error %.2g°", worstTurn),
                        finite ? std::max(worstNorm, worstTurn) : INFINITY, 1e-6, "(norm or °)"));
}

void turntableQuarter(std::vector<StabilityCase>& out) {
    Scene sc;
    sc.geometry.spheres.push_back({Vec3(0.f), 1.f, 0});
    sc.materials.resize(1);
    sc.build();
    anim::TurntableSettings s;
    s.seconds = 4.0;
    s.fps = 30.0;
    const anim::Turntable t = anim::Turntable::framed(s, sc);
    const int n = t.frameCount();
    const double yaw = t.yawAtFrame(n / 4) * 180.0 / kPi;
    out.push_back(check("25", "turntable of " + std::to_string(n) + " frames: yaw at frame N/4",
                        formatValue("%.12f°", yaw), std::abs(yaw - 90.0), 1e-9, "degrees"));
}

void cubicSpline(std::vector<StabilityCase>& out) {
    anim::KeyTrack track(1, false);
    const double v0 = 0.0, v1 = 16.0, m = 8.0;
    track.addKey(0.0, &v0, anim::Interp::Hermite, nullptr, &m);
    track.addKey(2.0, &v1, anim::Interp::Hermite, &m, nullptr);
    const double v = track.evaluateScalar(0.5);
    out.push_back(check("26", "CUBICSPLINE keys 0→16 over 2 s, tangents 8/s, at 0.5 s",
                        formatValue("v = %.12g (4.0; unscaled tangents give 3.25)", v), std::abs(v - 4.0), 1e-12, ""));
}

void keyRules(std::vector<StabilityCase>& out) {
    int broken = 0;
    anim::KeyTrack track(1, false);
    const double a = 1.0 / 3.0, b = 7.0;
    track.addKey(0.1, &a, anim::Interp::Linear);
    track.addKey(0.7, &b, anim::Interp::Linear);
    try {
        track.addKey(0.7, &a, anim::Interp::Linear);  // equal time: must be refused
        ++broken;
    } catch (const anim::KeyError&) {
    }
    broken += track.evaluateScalar(0.1) != a;   // bit-exact at a key
    broken += track.evaluateScalar(0.7) != b;
    broken += track.evaluateScalar(-5.0) != a;  // clamped outside
    broken += track.evaluateScalar(1e9) != b;
    anim::KeyTrack step(1, false);
    step.addKey(0.0, &a, anim::Interp::Step);
    step.addKey(1.0, &b, anim::Interp::Step);
    broken += step.evaluateScalar(0.999) != a;  // STEP holds
    out.push_back(check("27", "key rules: equal times refused, exact at keys, clamped, STEP holds",
                        std::to_string(broken) + " of 6 rules broken", broken, 0.0, "rules broken"));
}

void catmullRomDuplicates(std::vector<StabilityCase>& out) {
    anim::KeyTrack track(3, false);
    const double p[4][3] = {{0, 0, 0}, {0, 0, 0}, {1, 2, 3}, {1, 2, 3}};
    for (int k = 0; k < 4; ++k) track.addKey(double(k), p[k], anim::Interp::CatmullRom);
    int bad = 0;
    for (int i = 0; i <= 300; ++i) {
        const DVec3 v = track.evaluateVec3(i * 0.01);
        bad += !(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    }
    out.push_back(check("28", "centripetal Catmull–Rom through duplicated points",
                        std::to_string(bad) + " of 301 samples not finite", bad, 0.0, "non-finite samples"));
}

void lookAtDegenerate(std::vector<StabilityCase>& out) {
    double worst = 0.0;
    const Vec3 ups[] = {Vec3(0, 1, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    const Vec3 eyes[] = {Vec3(0, 5, 0), Vec3(1, 2, 3), Vec3(0, 0, 0)};
    const Vec3 targets[] = {Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(0, 0, -7)};
    for (int i = 0; i < 3; ++i) {
        const CameraBasis b = lookAt(eyes[i], targets[i], ups[i]);
        // Right-handed with the camera looking down its −z: (right, up, −forward) has det +1.
        const glm::dmat3 m(DVec3(b.right), DVec3(b.up), -DVec3(b.forward));
        const double det = glm::determinant(m);
        const double ortho = std::max({std::abs(glm::dot(b.right, b.up)), std::abs(glm::dot(b.up, b.forward)),
                                       std::abs(glm::dot(b.right, b.forward))});
        const double e = std::max(std::abs(det - 1.0), double(ortho));
        worst = std::isfinite(e) ? std::max(worst, e) : INFINITY;
    }
    out.push_back(check("29", "lookAt with forward ∥ up, eye = target",
                        formatValue("worst |det−1| or off-orthogonality %.2g", worst), worst, 1e-5, ""));
}

}  // namespace

void runTimelineCases(std::vector<StabilityCase>& out) {
    shortPath(out);
    slerpEdges(out);
    turntableQuarter(out);
    cubicSpline(out);
    keyRules(out);
    catmullRomDuplicates(out);
    lookAtDegenerate(out);
}

void frameTimeCases(std::vector<StabilityCase>& out) {
    const double t = anim::frameTime(0.0, 30.0, 100000);
    const double expect = 100000.0 / 30.0;
    // The accumulated sum a naive player computes, for contrast.
    double acc = 0.0;
    for (int i = 0; i < 100000; ++i) acc += 1.0 / 30.0;
    StabilityCase c{"30", "time of frame 100000 at 30 fps, from the index", formatValue("%.12f s", t), std::abs(t - expect),
                    0.0, "s", false, false};
    c.pass = t == expect;
    out.push_back(c);
    out.push_back({"30", "the same accumulated frame by frame (naive)", formatValue("%.12f s", acc), std::abs(acc - expect),
                   0.0, "s", false, true});
}

}  // namespace rf::report
