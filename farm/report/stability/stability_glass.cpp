// Glass through a smooth-shaded mesh refracts as the smooth surface: a 64 × 32 UV sphere mesh
// against the analytic sphere of the same glass (see docs/pictures.md, "Glass through smooth
// meshes", for the rule on shading normals that disagree with the facet).
#include <cmath>

#include "engine/util/image.h"
#include "farm/report/stability/stability_cases.h"
#include "farm/report/stability/stability_scenes.h"

namespace rf::stability {

namespace {

TriangleMesh smoothUvSphere(int rings, int segs, float radius, const Vec3& c, int material) {
    TriangleMesh m;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segs; ++j) {
            const float th = kPi * float(i) / float(rings), ph = 2.f * kPi * float(j % segs) / float(segs);
            const Vec3 n(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
            m.positions.push_back(c + radius * n);
            m.normals.push_back(n);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            const uint32_t a = uint32_t(i * (segs + 1) + j), b = a + 1, d = a + uint32_t(segs) + 1, e = d + 1;
            if (i > 0) m.indices.insert(m.indices.end(), {a, b, d});
            if (i < rings - 1) m.indices.insert(m.indices.end(), {b, e, d});
        }
    m.material = material;
    return m;
}

Scene glassOverChecker(bool mesh) {
    Scene s;
    Material floor = matte(Color(0.9f));
    floor.specular = 0.f;
    floor.color2 = Color(0.1f, 0.2f, 0.5f);
    floor.checkerScale = 1.f;
    Material glass;
    glass.gltfPbr = true;
    glass.color = Color(1.f);
    glass.metallic = 0.f;
    glass.roughness = 0.f;
    glass.transmission = 1.f;
    glass.ior = 1.5f;
    s.materials = {floor, glass};
    s.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    const Vec3 c(0.f, 1.f, 0.f);
    if (mesh) s.geometry.meshes.push_back(smoothUvSphere(32, 64, 1.f, c, 1));
    else s.geometry.spheres.push_back({c, 1.f, 1});
    Light l;
    l.position = Vec3(1.5f, 6.f, -1.f);
    s.lights = {l};
    s.background = Color(0.3f, 0.35f, 0.4f);
    s.camera.eye = Vec3(0.f, 3.2f, 4.f);
    s.camera.target = Vec3(0.f, 0.7f, 0.f);
    s.camera.fovDeg = 40.f;
    s.build();
    return s;
}

}  // namespace

void smoothGlassMesh(std::vector<StabilityCase>& out, int threads) {
    const std::vector<uint8_t> ref = render8(glassOverChecker(false), 192, 128, 4, threads);
    const std::vector<uint8_t> ours = render8(glassOverChecker(true), 192, 128, 4, threads);
    double sum2 = 0.0;
    for (size_t i = 0; i < ref.size(); ++i) sum2 += double(int(ours[i]) - int(ref[i])) * double(int(ours[i]) - int(ref[i]));
    const double rms = std::sqrt(sum2 / double(ref.size()));
    StabilityCase c{"glass", "64 × 32 smooth UV sphere mesh of glass against the analytic sphere", "", rms, 4.0,
                    "8-bit levels RMS", rms <= 4.0, false};
    c.measured = "RMS " + formatValue("%.2f", rms) + " levels over 192×128 pixels, 4 spp (refracting on facet normals: about 16)";
    out.push_back(c);
}

}  // namespace rf::stability
