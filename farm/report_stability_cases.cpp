// The cases of `rayfarm report --stability`, built with the engine's API (Scene fields, build())
// or, where the loader's own rebasing is what is tested, from a scene file in memory.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "frame_time.h"
#include "image.h"
#include "render.h"
#include "report_stability.h"
#include "scene.h"
#include "scene_loader.h"

namespace rf::report {

namespace {

constexpr int kW = 128, kH = 72;  // small: every case together runs in seconds

std::string fmt(const char* f, double v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

Material matte(const Color& c, float reflection = 0.f) {
    Material m;
    m.color = c;
    m.ambient = 0.1f;
    m.diffuse = 0.9f;
    m.specular = 0.4f;
    m.shininess = 30.f;
    m.reflection = reflection;
    return m;
}

/// A floor with a checker, three spheres (one a mirror) and two point lights, all scaled by s
/// about the origin: with no absolute epsilon anywhere, the picture must not change.
Scene demoScene(float s) {
    Scene sc;
    Material floor = matte(Color(0.9f), 0.1f);
    floor.color2 = Color(0.15f);
    floor.checkerScale = 1.0f * s;
    sc.materials = {floor, matte(Color(0.8f, 0.15f, 0.1f)), matte(Color(0.95f), 0.9f), matte(Color(0.1f, 0.4f, 0.85f))};
    sc.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    sc.spheres.push_back({Vec3(-1.6f, 0.8f, 0.3f) * s, 0.8f * s, 1});
    sc.spheres.push_back({Vec3(0.4f, 1.0f, 0.0f) * s, 1.0f * s, 2});
    sc.spheres.push_back({Vec3(2.0f, 0.5f, -1.2f) * s, 0.5f * s, 3});
    Light a, b;
    a.position = Vec3(6, 9, -5) * s;
    b.position = Vec3(-7, 6, -8) * s;
    b.color = Color(0.5f, 0.5f, 0.6f);
    sc.lights = {a, b};
    sc.background = Color(0.05f, 0.07f, 0.12f);
    sc.camera.eye = Vec3(0, 2.5f, -7) * s;
    sc.camera.target = Vec3(0, 0.8f, 0) * s;
    sc.camera.fovDeg = 55.f;
    sc.camera.fovHorizontal = true;
    sc.build();
    return sc;
}

std::vector<uint8_t> render8(const Scene& sc, int w, int h, int spp, int threads) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.spp = spp;
    s.maxDepth = 5;
    RayStats rays;
    return toRgb8(renderFrame(sc, sc.camera, s, 0, threads, rays), s);
}

/// Share of pixels whose every channel differs by at most `levels` 8-bit steps.
double fractionWithin(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int levels) {
    size_t ok = 0, n = a.size() / 3;
    for (size_t i = 0; i < n; ++i) {
        bool same = true;
        for (int c = 0; c < 3; ++c) same &= std::abs(int(a[3 * i + c]) - int(b[3 * i + c])) <= levels;
        ok += same;
    }
    return double(ok) / double(n);
}

/// Image-agreement case: pass when at least 99.9% of pixels are within 1/255 (catalogue #21).
StabilityCase imageCase(const std::string& id, const std::string& name, const std::vector<uint8_t>& a,
                        const std::vector<uint8_t>& b, bool informative = false) {
    const double f = fractionWithin(a, b, 1);
    StabilityCase c{id, name, fmt("%.3f%% of pixels within 1/255", 100.0 * f), 100.0 * (1.0 - f), 0.1,
                    "% pixels off", false, informative};
    c.pass = c.error <= c.tolerance;
    return c;
}

void scaleSweep(std::vector<StabilityCase>& out, int threads) {
    const std::vector<uint8_t> ref = render8(demoScene(1.f), kW, kH, 1, threads);
    for (float s : {1e-4f, 1e5f})
        out.push_back(imageCase("21", "whole scene scaled by " + fmt("%g", s) + " against scale 1",
                                render8(demoScene(s), kW, kH, 1, threads), ref));
}

void farSmallSphere(std::vector<StabilityCase>& out) {
    Scene sc;
    sc.materials = {matte(Color(1.f))};
    sc.spheres.push_back({Vec3(0.f), 0.1f, 0});
    sc.build();
    for (float x0 : {-400.f, -1e4f, -1e7f}) {
        Ray r;
        r.o = Vec3(x0, 0.095f, 0.f);
        r.d = Vec3(1.f, 0.f, 0.f);
        Hit hit;
        const bool found = sc.intersect(r, hit);
        const double expect = -double(x0) - std::sqrt(0.1 * 0.1 - double(0.095f) * double(0.095f));
        float tNaive = 0.f;
        const bool naive = intersectSphereNaive(sc.spheres[0], r, 0.f, kInf, tNaive);
        StabilityCase c{"1", "sphere r 0.1, ray from x = " + fmt("%g", x0) + " at y 0.095", "", 0.0, 1e-6,
                        "relative t", false, false};
        c.error = found ? std::abs(double(hit.t) - expect) / expect : 1.0;
        c.measured = std::string(found ? "hit" : "MISSED") + ", t " + (found ? fmt("%.9g", hit.t) : "-") +
                     " vs " + fmt("%.9g", expect) + "; textbook quadratic " + (naive ? "hits" : "misses");
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
    sc.meshes.push_back(m);
    sc.build();
    Ray r;
    r.o = Vec3(0, 0, 10);
    r.d = Vec3(0.30458447f, 0.30458447f, -0.9024725f);
    Hit hit;
    const bool found = sc.intersect(r, hit);
    const Vec3 p = r.o + hit.t * r.d;
    StabilityCase c{"4", "ray onto the diagonal seam of two triangles", "", 0.0, 1e-4, "distance", false, false};
    c.error = found ? double(glm::length(p - Vec3(3.375f, 3.375f, 0.f))) : 1e30;
    c.measured = found ? "hit at t " + fmt("%.6g", hit.t) + " (expected 11.0807)" : "MISSED both triangles";
    c.pass = found && c.error <= c.tolerance && std::abs(hit.t - 11.0807f) < 1e-3f;
    out.push_back(c);
}

/// Icosphere of radius r (subdivided icosahedron): a closed mesh with shared vertices and edges.
TriangleMesh icosphere(int levels, float radius, const Vec3& centre) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<DVec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                               11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                               3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (DVec3& p : v) p = glm::normalize(p);
    for (int l = 0; l < levels; ++l) {
        std::vector<uint32_t> g;
        std::vector<std::pair<uint64_t, uint32_t>> cache;
        auto mid = [&](uint32_t a, uint32_t b) {
            const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            for (const auto& [k, i] : cache)
                if (k == key) return i;
            v.push_back(glm::normalize(v[a] + v[b]));
            cache.push_back({key, uint32_t(v.size() - 1)});
            return uint32_t(v.size() - 1);
        };
        for (size_t i = 0; i < f.size(); i += 3) {
            const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            const uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        f = g;
    }
    TriangleMesh m;
    for (const DVec3& p : v) m.positions.push_back(Vec3(p * double(radius)) + centre);
    m.indices = f;
    return m;
}

void watertight(std::vector<StabilityCase>& out) {
    const Vec3 centre(0.3f, -0.2f, 0.1f);
    Scene sc;
    sc.materials = {matte(Color(1.f))};
    sc.meshes.push_back(icosphere(2, 1.f, centre));
    sc.build();
    const TriangleMesh& m = sc.meshes[0];
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
        if (!sc.intersect(r, hit)) ++missed;
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
    sc.spheres.push_back({Vec3(0.f), 1.f, 0});
    sc.spheres.push_back({Vec3(0.f), 1.f + 4e-5f, 0});
    sc.build();
    // As the tracer does: hit the outer shell, spawn a ray inward from the offset hit point, and
    // it must stop at the inner sphere 4e-5 further on, not skip it.
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
        if (!sc.intersect(r, hit)) continue;
        const SurfaceInteraction si = sc.interaction(r, hit);
        Ray in;
        in.d = r.d;
        in.o = offsetRayOrigin(si.p, si.pError, si.ng, in.d);
        Hit h2;
        ++rays;
        const double gap = glm::length(DVec3(in.o)) - 1.0;  // radial distance to the inner sphere
        if (!sc.intersect(in, h2) || std::abs(h2.t - gap) > 0.25 * 4e-5) {
            ++missed;
            continue;
        }
        worst = std::max(worst, std::abs(h2.t - gap) / 4e-5);
    }
    StabilityCase c{"12", "spheres r 1 and 1 + 4e-5: ray spawned inward from the outer one", "", double(missed), 0.0,
                    "rays skipping the inner sphere", false, false};
    c.measured = std::to_string(missed) + " of " + std::to_string(rays) + " skipped it; worst t error " +
                 fmt("%.2g", worst) + " of the gap";
    c.pass = missed == 0 && rays > 0;
    out.push_back(c);
}

std::string jsonScene(double dx) {
    std::ostringstream j;
    j.precision(17);
    auto p = [&](double x, double y, double z) {
        std::ostringstream s;
        s.precision(17);
        s << "[" << x + dx << ", " << y << ", " << z << "]";
        return s.str();
    };
    j << "{\"camera\": {\"eye\": " << p(0, 2.5, -7) << ", \"target\": " << p(0, 0.8, 0)
      << ", \"up\": [0,1,0], \"fov\": 55, \"fov_axis\": \"horizontal\"},"
      << "\"background\": [0.05, 0.07, 0.12],"
      << "\"materials\": {\"floor\": {\"color\": [0.9,0.9,0.9], \"checker\": {\"color2\": [0.15,0.15,0.15], "
         "\"scale\": 1}, \"ambient\": 0.1, \"diffuse\": 0.8, \"reflection\": 0.1},"
      << "\"red\": {\"color\": [0.8,0.15,0.1], \"diffuse\": 0.8, \"specular\": 0.5, \"shininess\": 40},"
      << "\"mirror\": {\"color\": [0.95,0.95,0.95], \"diffuse\": 0.05, \"reflection\": 0.9}},"
      << "\"lights\": [{\"type\": \"point\", \"position\": " << p(6, 9, -5) << "}],"
      << "\"objects\": [{\"type\": \"plane\", \"normal\": [0,1,0], \"point\": " << p(0, 0, 0)
      << ", \"material\": \"floor\"},"
      << "{\"type\": \"sphere\", \"center\": " << p(-1.6, 0.8, 0.3) << ", \"radius\": 0.8, \"material\": \"red\"},"
      << "{\"type\": \"sphere\", \"center\": " << p(0.4, 1.0, 0) << ", \"radius\": 1.0, \"material\": \"mirror\"}]}";
    return j.str();
}

Scene loadFromText(const std::string& name, const std::string& text) {
    FileBundle b;
    b.files[name] = text;
    BundleFileSource fs(b);
    return loadJsonScene(name, fs);
}

void translatedModel(std::vector<StabilityCase>& out, int threads) {
    const Scene origin = loadFromText("origin.json", jsonScene(0.0));
    const Scene far = loadFromText("far.json", jsonScene(6.4e6));
    const std::vector<uint8_t> ref = render8(origin, kW, kH, 1, threads);
    out.push_back(imageCase("22", "scene file translated to x = 6.4e6 (loader rebases to the camera)",
                            render8(far, kW, kH, 1, threads), ref));
    // The same scene with float world coordinates (no rebasing): float spacing at 6.4e6 is 0.5.
    Scene naive = origin;
    const Vec3 shift(6.4e6f, 0.f, 0.f);
    for (Sphere& s : naive.spheres) s.center += shift;
    for (Plane& p : naive.planes) p.d -= glm::dot(p.n, shift);
    for (Light& l : naive.lights) l.position += shift;
    naive.camera.eye += shift;
    naive.camera.target += shift;
    naive.renderOrigin -= DVec3(shift);  // world positions unchanged, only the float frame moves
    naive.build();
    out.push_back(imageCase("22", "the same at x = 6.4e6 in float world coordinates (no rebasing)",
                            render8(naive, kW, kH, 1, threads), ref, true));
}

void distanceInvariance(std::vector<StabilityCase>& out, int threads) {
    auto scene = [](float dist) {
        Scene sc;
        sc.materials = {matte(Color(0.8f, 0.3f, 0.2f))};
        sc.spheres.push_back({Vec3(0.f), 1.f, 0});
        Light l;
        l.position = Vec3(3, 4, 5);
        sc.lights = {l};
        sc.camera.eye = Vec3(0, 0, dist);
        sc.camera.target = Vec3(0.f);
        sc.camera.fovDeg = float(2.0 * std::atan(1.5 / dist) * 180.0 / 3.14159265358979);
        sc.build();
        return sc;
    };
    // The catalogue pairs 10 and 1000; at 10 the perspective itself differs (a 5.7° cone onto the
    // sphere, not 0.06°), so the pair compared here is 1000 and 1e5, where only precision can differ.
    out.push_back(imageCase("3", "unit sphere from distance 1e5 against 1000, field of view scaled",
                            render8(scene(1e5f), kW, kH, 1, threads), render8(scene(1000.f), kW, kH, 1, threads)));
}

void selfShadowAtRange(std::vector<StabilityCase>& out, int threads) {
    Scene sc;
    Material m = matte(Color(1.f));
    m.ambient = 0.f;
    m.specular = 0.f;
    sc.materials = {m};
    sc.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    Light l;
    l.type = LightType::Directional;
    l.direction = glm::normalize(Vec3(0.3f, -1.f, 0.2f));
    sc.lights = {l};
    sc.camera.eye = Vec3(0.f, 0.6e6f, -0.8e6f);
    sc.camera.target = Vec3(0.f);
    sc.camera.fovDeg = 0.002f;
    sc.build();
    const std::vector<uint8_t> img = render8(sc, kW, kH, 1, threads);
    const int lit = toByte(srgbEncode(toneMap(m.diffuse * -l.direction.y, ToneMap::Clamp)));
    int dark = 0;
    for (size_t i = 0; i < img.size(); i += 3) dark += std::abs(int(img[i]) - lit) > 1;
    StabilityCase c{"11", "lit plane seen from 1e6 away", "", double(dark), 0.0, "pixels self-shadowed", false, false};
    c.measured = std::to_string(dark) + " of " + std::to_string(kW * kH) + " pixels differ from the lit value " +
                 std::to_string(lit);
    c.pass = dark == 0;
    out.push_back(c);
}

void lightJustAbovePlane(std::vector<StabilityCase>& out, int threads) {
    Scene sc;
    Material m = matte(Color(1.f));
    m.ambient = 0.f;
    m.specular = 0.f;
    m.diffuse = 1.f;
    sc.materials = {m};
    sc.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    Light l;
    l.position = Vec3(0.f, 1e-3f, 0.f);
    sc.lights = {l};
    sc.camera.eye = Vec3(0.f, 1.f, 0.f);
    sc.camera.target = Vec3(0.f);
    sc.camera.up = Vec3(0, 0, 1);
    sc.camera.fovDeg = 0.005f;  // the view spans ~1e-4, where cos θ to the light stays above 0.99
    sc.build();
    const std::vector<uint8_t> img = render8(sc, 32, 32, 1, threads);
    int dark = 0;
    for (size_t i = 0; i < img.size(); i += 3) dark += img[i] < 250;
    StabilityCase c{"14", "point light 1e-3 above a plane", "", double(dark), 0.0, "unlit pixels", false, false};
    c.measured = std::to_string(dark) + " of 1024 pixels under the light are unlit";
    c.pass = dark == 0;
    out.push_back(c);
}

void frameTimes(std::vector<StabilityCase>& out) {
    const double t = anim::frameTime(0.0, 30.0, 100000);
    const double expect = 100000.0 / 30.0;
    // The accumulated sum a naive player computes, for contrast.
    double acc = 0.0;
    for (int i = 0; i < 100000; ++i) acc += 1.0 / 30.0;
    StabilityCase c{"30", "time of frame 100000 at 30 fps, from the index", fmt("%.12f s", t), std::abs(t - expect),
                    0.0, "s", false, false};
    c.pass = t == expect;
    out.push_back(c);
    out.push_back({"30", "the same accumulated frame by frame (naive)", fmt("%.12f s", acc), std::abs(acc - expect),
                   0.0, "s", false, true});
}

}  // namespace

std::vector<StabilityCase> runStabilityCases(int threads) {
    std::vector<StabilityCase> out;
    farSmallSphere(out);
    distanceInvariance(out, threads);
    triangleSeam(out);
    watertight(out);
    selfShadowAtRange(out, threads);
    thinGap(out);
    lightJustAbovePlane(out, threads);
    scaleSweep(out, threads);
    translatedModel(out, threads);
    runTimelineCases(out);
    frameTimes(out);
    return out;
}

}  // namespace rf::report
