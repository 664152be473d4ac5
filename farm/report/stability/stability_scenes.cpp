#include "farm/report/stability/stability_scenes.h"

#include <cmath>
#include <cstdio>

#include "engine/util/image.h"
#include "engine/integrators/render.h"

namespace rf::stability {

std::string formatValue(const char* format, double v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

Material matte(const Color& c, float reflection) {
    Material m;
    m.color = c;
    m.ambient = 0.1f;
    m.diffuse = 0.9f;
    m.specular = 0.4f;
    m.shininess = 30.f;
    m.reflection = reflection;
    return m;
}

Scene demoScene(float s) {
    Scene sc;
    Material floor = matte(Color(0.9f), 0.1f);
    floor.color2 = Color(0.15f);
    floor.checkerScale = 1.0f * s;
    sc.materials = {floor, matte(Color(0.8f, 0.15f, 0.1f)), matte(Color(0.95f), 0.9f), matte(Color(0.1f, 0.4f, 0.85f))};
    sc.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    sc.geometry.spheres.push_back({Vec3(-1.6f, 0.8f, 0.3f) * s, 0.8f * s, 1});
    sc.geometry.spheres.push_back({Vec3(0.4f, 1.0f, 0.0f) * s, 1.0f * s, 2});
    sc.geometry.spheres.push_back({Vec3(2.0f, 0.5f, -1.2f) * s, 0.5f * s, 3});
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
    return toRgb8(renderFrame(sc, {sc.camera, s}, 0, threads, rays), s);
}

namespace {

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

}  // namespace

StabilityCase imageCase(const std::string& id, const std::string& name, const std::vector<uint8_t>& a,
                        const std::vector<uint8_t>& b, bool informative) {
    const double f = fractionWithin(a, b, 1);
    StabilityCase c{id, name, formatValue("%.3f%% of pixels within 1/255", 100.0 * f), 100.0 * (1.0 - f), 0.1,
                    "% pixels off", false, informative};
    c.pass = c.error <= c.tolerance;
    return c;
}

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
}  // namespace rf::stability
