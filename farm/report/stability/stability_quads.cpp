// Catalogue #11 on triangles: a flat, uniformly lit quad of two triangles must show one value on
// every pixel wherever it lies. A shadow ray that meets its own triangle or the neighbour across
// the diagonal (self-intersection) darkens some samples: speckle and a band along the diagonal.
#include <cmath>

#include "farm/report/stability/stability_cases.h"
#include "farm/report/stability/stability_scenes.h"

namespace rf::stability {

namespace {

constexpr int kQuadSide = 48;
constexpr int kQuadSpp = 4;  // jittered samples: each lands on a different point of the quad

/// The quad (half-size 1) centred at (0, 0, z), turned by tilt degrees about x, seen head-on
/// from 3 units along its normal so that it fills the whole frame; two directional lights that
/// cast shadows, one of them grazing (75° off the normal); Lambert only, no ambient.
Scene flatQuadScene(float z, float tiltDeg) {
    const float a = glm::radians(tiltDeg);
    const Vec3 c(0.f, 0.f, z);
    const Vec3 u(1.f, 0.f, 0.f), v(0.f, std::cos(a), std::sin(a)), n(0.f, -std::sin(a), std::cos(a));
    Scene sc;
    Material m = matte(Color(1.f));
    m.ambient = 0.f;
    m.specular = 0.f;
    m.diffuse = 0.8f;
    sc.materials = {m};
    TriangleMesh q;
    q.positions = {c - u - v, c + u - v, c + u + v, c - u + v};
    q.indices = {0, 1, 2, 0, 2, 3};
    q.material = 0;
    sc.geometry.meshes.push_back(q);
    Light key, graze;
    key.type = graze.type = LightType::Directional;
    key.direction = -glm::normalize(0.5f * u + 0.3f * v + n);
    key.intensity = 0.6f;
    const float g = glm::radians(75.f);
    graze.direction = -glm::normalize(std::sin(g) * glm::normalize(-0.4f * u + v) + std::cos(g) * n);
    graze.intensity = 0.4f;
    key.castShadows = graze.castShadows = true;
    sc.lights = {key, graze};
    sc.background = Color(0.f);
    sc.camera.eye = c + 3.f * n;
    sc.camera.target = c;
    sc.camera.up = v;
    sc.camera.fovDeg = 30.f;  // the quad spans 37° from 3 away: every pixel is inside it
    sc.build();
    return sc;
}

}  // namespace

double flatQuadSpeckle(float z, float tiltDeg, int threads) {
    const std::vector<uint8_t> img = render8(flatQuadScene(z, tiltDeg), kQuadSide, kQuadSide, kQuadSpp, threads);
    double sum = 0.0, sum2 = 0.0;
    const size_t n = img.size() / 3;
    for (size_t i = 0; i < img.size(); i += 3) {
        sum += img[i];
        sum2 += double(img[i]) * img[i];
    }
    const double mean = sum / double(n);
    return std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean));
}

void flatQuads(std::vector<StabilityCase>& out, int threads) {
    for (float z : {1e-3f, 1e3f, 1e5f})
        for (float tilt : {0.f, 30.f, 60.f}) {
            const double sd = flatQuadSpeckle(z, tilt, threads);
            StabilityCase c{"11", "flat lit quad (2 triangles) at z = " + formatValue("%g", z) + ", tilted " +
                                      formatValue("%g", tilt) + "°",
                            "", sd, kQuadSpeckleBound, "8-bit levels (s.d.)", false, false};
            c.measured = "standard deviation " + formatValue("%.3f", sd) + " over all " +
                         std::to_string(kQuadSide * kQuadSide) + " pixels, " + std::to_string(kQuadSpp) + " spp";
            c.pass = sd <= kQuadSpeckleBound;
            out.push_back(c);
        }
}

}  // namespace rf::stability
