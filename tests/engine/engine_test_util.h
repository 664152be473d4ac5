#pragma once
// Small scene builders and image helpers shared by the engine-core tests.
#include <cmath>
#include <string>
#include <vector>

#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/scene/scene.h"

namespace rf::test {

/// A scene with one default material (index 0) and nothing else.
inline Scene emptyScene() {
    Scene s;
    s.materials.push_back(Material{});
    s.background = Color(0.f);
    return s;
}

/// Lambert-only material: ambient ka, diffuse kd, colour c.
inline Material matte(const Color& c, float ka = 0.1f, float kd = 0.9f) {
    Material m;
    m.color = c;
    m.ambient = ka;
    m.diffuse = kd;
    m.specular = 0.f;
    return m;
}

/// UV sphere of `rings` × `segs` quads; smooth = per-vertex normals (Phong shading).
inline TriangleMesh uvSphere(int rings, int segs, float radius, const Vec3& c, bool smooth, int material = 0) {
    TriangleMesh m;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segs; ++j) {
            const float th = kPi * i / rings, ph = 2.f * kPi * (j % segs) / segs;
            const Vec3 n(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
            m.positions.push_back(c + radius * n);
            if (smooth) m.normals.push_back(n);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            const uint32_t a = i * (segs + 1) + j, b = a + 1, d = a + segs + 1, e = d + 1;
            if (i > 0) m.indices.insert(m.indices.end(), {a, b, d});          // outward winding
            if (i < rings - 1) m.indices.insert(m.indices.end(), {b, e, d});
        }
    m.material = material;
    return m;
}

/// n × n quads in the plane y = 0 over [−half, half]², normals up.
inline TriangleMesh gridMesh(int n, float half, int material = 0) {
    TriangleMesh m;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            m.positions.emplace_back(-half + 2.f * half * j / n, 0.f, -half + 2.f * half * i / n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const uint32_t a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    m.material = material;
    return m;
}

inline RenderSettings smallSettings(int w, int h, int spp = 1, int depth = 5) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.spp = spp;
    s.maxDepth = depth;
    return s;
}

/// Renders the scene's camera on one thread.
inline Image render(const Scene& scene, const RenderSettings& s, RayStats* statsOut = nullptr, int threads = 1) {
    RayStats st;
    Image img = renderFrame(scene, {scene.camera, s}, 0, threads, st);
    if (statsOut) *statsOut = st;
    return img;
}

/// Fraction of pixels whose 8-bit sRGB values differ by more than `tol` levels in some channel.
inline double fractionOff(const Image& a, const Image& b, int tol = 1, ToneMap op = ToneMap::Clamp) {
    const std::vector<uint8_t> x = toRgb8(a, op), y = toRgb8(b, op);
    size_t off = 0;
    for (size_t p = 0; p < x.size(); p += 3) {
        bool bad = false;
        for (int c = 0; c < 3; ++c) bad |= std::abs(int(x[p + c]) - int(y[p + c])) > tol;
        off += bad;
    }
    return double(off) / double(x.size() / 3);
}

inline bool allFinite(const Image& img) {
    const size_t n = size_t(img.width()) * img.height() * 3;
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(img.data()[i])) return false;
    return true;
}

}  // namespace rf::test
