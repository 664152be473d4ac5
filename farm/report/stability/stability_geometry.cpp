// Geometric cases of the catalogue: rays against spheres and meshes through SceneGeometry::intersect,
// the way the tracer casts them, each measured against an exact or double-precision answer.
#include <algorithm>
#include <cmath>
#include <random>

#include "engine/geometry/shapes.h"
#include "farm/report/stability/stability_cases.h"
#include "farm/report/stability/stability_scenes.h"

namespace rf::stability {

void farSmallSphere(std::vector<StabilityCase>& out) {
    Scene sc;
    sc.materials = {matte(Color(1.f))};
    sc.geometry.spheres.push_back({Vec3(0.f), 0.1f, 0});
    sc.build();
    for (float x0 : {-400.f, -1e4f, -1e7f}) {
        Ray r;
        r.o = Vec3(x0, 0.095f, 0.f);
        r.d = Vec3(1.f, 0.f, 0.f);
        Hit hit;
        const bool found = sc.geometry.intersect(r, hit);
        const double expect = -double(x0) - std::sqrt(0.1 * 0.1 - double(0.095f) * double(0.095f));
        float tNaive = 0.f;
        const bool naive = intersectSphereNaive(sc.geometry.spheres[0], r, 0.f, kInf, tNaive);
        StabilityCase c{"1", "sphere r 0.1, ray from x = " + formatValue("%g", x0) + " at y 0.095", "", 0.0, 1e-6,
                        "relative t", false, false};
        c.error = found ? std::abs(double(hit.t) - expect) / expect : 1.0;
        c.measured = std::string(found ? "hit" : "MISSED") + ", t " + (found ? formatValue("%.9g", hit.t) : "-") +
                     " vs " + formatValue("%.9g", expect) + "; textbook quadratic " + (naive ? "hits" : "misses");
        // float t cannot be better than half an ulp of t itself: tolerance 1e-6 is ~8 ulps.
        c.pass = found && c.error <= c.tolerance;
        out.push_back(c);
    }
}

void triangleSeam(std::vector<StabilityCase>& out) {
    Scene sc;
    sc.materials = {matte(Color(1.f))};
    TriangleMesh m;
    m.positions = {Vec3(-5, -5, 0), Vec3(5, -5, 0), Vec3(5, 5, 0), Vec3(-5, 5, 0)};
    m.indices = {0, 1, 2, 0, 2, 3};
    sc.geometry.meshes.push_back(m);
    sc.build();
    Ray r;
    r.o = Vec3(0, 0, 10);
    r.d = Vec3(0.30458447f, 0.30458447f, -0.9024725f);
    Hit hit;
    const bool found = sc.geometry.intersect(r, hit);
    const Vec3 p = r.o + hit.t * r.d;
    StabilityCase c{"4", "ray onto the diagonal seam of two triangles", "", 0.0, 1e-4, "distance", false, false};
    c.error = found ? double(glm::length(p - Vec3(3.375f, 3.375f, 0.f))) : 1e30;
    c.measured = found ? "hit at t " + formatValue("%.6g", hit.t) + " (expected 11.0807)" : "MISSED both triangles";
    c.pass = found && c.error <= c.tolerance && std::abs(hit.t - 11.0807f) < 1e-3f;
    out.push_back(c);
}

void watertight(std::vector<StabilityCase>& out) {
    const Vec3 centre(0.3f, -0.2f, 0.1f);
    Scene sc;
    sc.materials = {matte(Color(1.f))};
    sc.geometry.meshes.push_back(icosphere(2, 1.f, centre));
    sc.build();
    const TriangleMesh& m = sc.geometry.meshes[0];
    // Inradius: the nearest face plane to the centre, from the float vertices in double.
    double inR = 1e30;
    for (size_t i = 0; i < m.indices.size(); i += 3) {
        const DVec3 a(m.positions[m.indices[i]]), b(m.positions[m.indices[i + 1]]), c(m.positions[m.indices[i + 2]]);
        const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
        inR = std::min(inR, std::abs(glm::dot(n, a - DVec3(centre))));
    }
    long mustHit = 0, missed = 0;
    auto shoot = [&](const Vec3& o, const Vec3& d) {
        // A line nearer the centre than the inradius (with a margin) surely enters the solid.
        const DVec3 oc = DVec3(o) - DVec3(centre), dd = glm::normalize(DVec3(d));
        const double dist = glm::length(oc - glm::dot(oc, dd) * dd);
        if (dist > inR * (1.0 - 1e-4)) return;
        ++mustHit;
        Ray r;
        r.o = o;
        r.d = d;
        Hit hit;
        if (!sc.geometry.intersect(r, hit)) ++missed;
    };
    // A grid along −z over the bounds; its lines x = 0 and y = 0 run along edges of the mesh.
    const int n = 256;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            shoot(centre + Vec3(-1.f + 2.f * i / n, -1.f + 2.f * j / n, 3.f), Vec3(0, 0, -1));
    // Rays aimed exactly at every vertex and at points along every edge, from many directions.
    std::mt19937 rng(12345);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    auto aimAt = [&](const Vec3& target) {
        for (int k = 0; k < 4; ++k) {
            const Vec3 o = centre + (target - centre) * 3.f + Vec3(u(rng), u(rng), u(rng));
            shoot(o, target - o);
        }
    };
    for (const Vec3& p : m.positions) aimAt(p);
    for (size_t i = 0; i < m.indices.size(); i += 3)
        for (int e = 0; e < 3; ++e) {
            const Vec3 a = m.positions[m.indices[i + e]], b = m.positions[m.indices[i + (e + 1) % 3]];
            for (float s : {0.5f, 0.25f, 1.f / 3.f}) aimAt(a + s * (b - a));
        }
    StabilityCase c{"5", "closed icosphere (320 triangles): grid along -z plus rays at every vertex and edge", "",
                    double(missed), 0.0, "rays missed", false, false};
    c.measured = std::to_string(missed) + " of " + std::to_string(mustHit) + " rays that enter the solid missed it";
    c.pass = missed == 0 && mustHit > 0;
    out.push_back(c);
}

void thinGap(std::vector<StabilityCase>& out) {
    Scene sc;
    sc.materials = {matte(Color(1.f))};
    sc.geometry.spheres.push_back({Vec3(0.f), 1.f, 0});
    sc.geometry.spheres.push_back({Vec3(0.f), 1.f + 4e-5f, 0});
    sc.build();
    // As the tracer does: hit the outer shell, spawn a ray inward from the offset hit point, and
    // it must stop at the inner sphere (prim 0) 4e-5 further on, not skip it.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    int missed = 0, rays = 0;
    double worst = 0.0;
    for (int k = 0; k < 64; ++k) {
        Vec3 dir = glm::normalize(Vec3(u(rng), u(rng), u(rng)));
        Ray r;
        r.o = dir * 5.f;
        r.d = -dir;
        Hit hit;
        if (!sc.geometry.intersect(r, hit)) continue;
        const SurfaceInteraction si = sc.geometry.interaction(r, hit);
        Ray in;
        in.d = r.d;
        in.o = offsetRayOrigin(si.p, si.pError, si.ng, in.d);
        Hit h2;
        ++rays;
        const double gap = glm::length(DVec3(in.o)) - 1.0;  // radial distance to the inner sphere
        const bool found = sc.geometry.intersect(in, h2, sc.geometry.skipFor(si, in.d));
        const double err = found ? std::abs(h2.t - gap) : 1.0;
        if (hit.prim != 1 || !found || h2.prim != 0 || err > 1e-6) ++missed;
        worst = std::max(worst, err);
    }
    StabilityCase c{"12", "spheres r 1 and 1 + 4e-5: ray spawned inward from the outer one", "", double(missed), 0.0,
                    "rays skipping the inner sphere or off by more than 1e-6", false, false};
    c.measured = std::to_string(missed) + " of " + std::to_string(rays) + " skipped it or missed t; worst t error " +
                 formatValue("%.2g", worst);
    c.pass = missed == 0 && rays > 0;
    out.push_back(c);
}
}  // namespace rf::stability
