#include "anim/turntable_fit.h"

#include <algorithm>
#include <cmath>

namespace rf::anim {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr int kSlices = 64;   ///< height bins
constexpr int kSectors = 64;  ///< angle bins around the axis

/// What one (slice, sector) bin holds: its vertices' largest distance from the axis and their
/// height range.
struct Bin {
    double rho = -1.0;  ///< < 0: empty
    double ylo = 0.0, yhi = 0.0;
    void add(double r, double y) {
        if (rho < 0.0) {
            rho = r;
            ylo = yhi = y;
            return;
        }
        rho = std::max(rho, r);
        ylo = std::min(ylo, y);
        yhi = std::max(yhi, y);
    }
};

/// Every vertex and sphere-box corner, relative to center.
std::vector<DVec3> scenePoints(const Scene& scene, const DVec3& center, bool staticOnly) {
    std::vector<DVec3> pts;
    for (const TriangleMesh& m : scene.geometry.meshes)
        if (!staticOnly || m.node < 0)
            for (const Vec3& p : m.positions) pts.push_back(DVec3(p) - center);
    for (const Sphere& s : scene.geometry.spheres) {
        Aabb b;
        b.grow(s.center - Vec3(s.radius));
        b.grow(s.center + Vec3(s.radius));
        for (const DVec3& c : boxCorners(b, center)) pts.push_back(c);
    }
    return pts;
}
}  // namespace

OrbitPose orbitPose(double yaw, double elevation) {
    const double ce = std::cos(elevation), se = std::sin(elevation);
    const DVec3 horizontal(std::sin(yaw), 0.0, std::cos(yaw));
    OrbitPose p;
    p.toEye = ce * horizontal + DVec3(0.0, se, 0.0);
    // At a pole the view is parallel to the world up; screen-up then points away from the camera
    // horizontally, which keeps the basis orthonormal and still turning with the yaw.
    p.up = std::abs(ce) < 1e-6 ? -std::copysign(1.0, se) * horizontal : DVec3(0.0, 1.0, 0.0);
    return p;
}

std::vector<DVec3> boxCorners(const Aabb& b, const DVec3& center) {
    std::vector<DVec3> out;
    if (b.empty()) return out;
    for (int i = 0; i < 8; ++i)
        out.push_back(DVec3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z) - center);
    return out;
}

std::vector<DVec3> silhouettePoints(const Scene& scene, const DVec3& center, bool staticOnly) {
    const std::vector<DVec3> pts = scenePoints(scene, center, staticOnly);
    if (pts.empty()) return pts;
    if (pts.size() <= 4 * kSectors) return pts;  // already few: exact
    double ylo = pts[0].y, yhi = pts[0].y;
    for (const DVec3& p : pts) {
        ylo = std::min(ylo, p.y);
        yhi = std::max(yhi, p.y);
    }
    const double perSlice = yhi > ylo ? kSlices / (yhi - ylo) : 0.0;
    std::vector<Bin> bins(size_t(kSlices) * kSectors);
    for (const DVec3& p : pts) {
        const int slice = std::clamp(int((p.y - ylo) * perSlice), 0, kSlices - 1);
        const double a = std::atan2(p.z, p.x);  // (−π, π]
        const int sector = std::clamp(int((a + kPi) * (kSectors / (2.0 * kPi))), 0, kSectors - 1);
        bins[size_t(slice) * kSectors + size_t(sector)].add(std::hypot(p.x, p.z), p.y);
    }
    // A sector of half-angle h with radius ρ lies in the triangle (axis, R·e_a, R·e_b) for
    // R = ρ / cos h: that triangle's far edge is ρ from the axis. Two sectors share each edge,
    // which takes the larger radius and both height ranges.
    const double grow = 1.0 / std::cos(kPi / kSectors);
    std::vector<DVec3> out;
    for (int s = 0; s < kSlices; ++s) {
        const Bin* row = &bins[size_t(s) * kSectors];
        Bin axis;
        for (int k = 0; k < kSectors; ++k) {
            const Bin& b = row[k];
            if (b.rho < 0.0) continue;
            axis.add(0.0, b.ylo);
            axis.add(0.0, b.yhi);
        }
        if (axis.rho < 0.0) continue;
        for (int e = 0; e < kSectors; ++e) {
            Bin edge;  // sectors e − 1 and e meet at angle −π + e·2π/kSectors
            for (const Bin* b : {&row[(e + kSectors - 1) % kSectors], &row[e]}) {
                if (b->rho < 0.0) continue;
                edge.add(b->rho, b->ylo);
                edge.add(b->rho, b->yhi);
            }
            if (edge.rho < 0.0) continue;
            const double a = -kPi + e * (2.0 * kPi / kSectors), r = edge.rho * grow;
            out.emplace_back(r * std::cos(a), edge.ylo, r * std::sin(a));
            out.emplace_back(r * std::cos(a), edge.yhi, r * std::sin(a));
        }
        out.emplace_back(0.0, axis.ylo, 0.0);  // the prisms' edges on the axis
        out.emplace_back(0.0, axis.yhi, 0.0);
    }
    return out;
}

OrbitFit fitOrbit(const std::vector<DVec3>& points, const OrbitView& view, double fill, double maxLift) {
    OrbitFit fit;
    if ((points.empty() && !view.framePoints) || view.yaws.empty() || !(fill > 0.0)) return fit;
    const double kx = fill * view.tanX, ky = fill * view.tanY;
    // With the look-at point c raised by lift Δ and s the depth of the orbit centre, a point at
    // camera coordinates (x, y, z) relative to the centre must keep |x| ≤ kx·(z + s) and
    // |y − Δ·a| ≤ ky·(z + s), a = up·Ŷ: three families of lines in (Δ, s), each family with one
    // slope, so only their largest offsets X, T and B matter.
    double X = -1e300, T = -1e300, B = -1e300;
    double a = 0.0, b = 0.0;
    for (size_t f = 0; f < view.yaws.size(); ++f) {
        const OrbitPose pose = orbitPose(view.yaws[f], view.elevation);
        const DVec3 fwd = -pose.toEye;
        const DVec3 right = glm::normalize(glm::cross(fwd, pose.up));
        const DVec3 up = glm::cross(right, fwd);
        if (f == 0) {
            a = up.y;
            b = fwd.y;
        }
        const DVec3 rightK = right / kx, upK = up / ky;  // so the loop has no division
        auto fitPoint = [&](const DVec3& p) {
            const double x = glm::dot(p, rightK), y = glm::dot(p, upK), z = glm::dot(p, fwd);
            X = std::max(X, std::abs(x) - z);
            T = std::max(T, y - z);
            B = std::max(B, -y - z);
        };
        for (const DVec3& p : points) fitPoint(p);
        if (view.framePoints) view.framePoints(f, fitPoint);
    }
    if (X < -1e299) return fit;  // no point at all
    // Centre the highest and lowest extents (T − Δ·a/ky = B + Δ·a/ky), then take the depth the
    // worst of the three needs.
    double lift = std::abs(a) > 1e-9 ? (T - B) * ky / (2.0 * a) : 0.0;
    lift = std::clamp(lift, -maxLift, maxLift);
    const double s = std::max({X, T - lift * a / ky, B + lift * a / ky});
    // s is the centre's depth; the eye sits at distance d from the raised look-at point.
    const double d = s + lift * b;
    if (!(d > 0.0) || !std::isfinite(d)) return fit;
    fit.distance = d;
    fit.lift = lift;
    return fit;
}

}  // namespace rf::anim
