#pragma once
/// Scenes, renders and image comparisons the stability cases share (internal to the library).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "farm/report/stability/stability_case.h"

namespace rf::stability {

constexpr int kW = 128, kH = 72;  // small: every case together runs in seconds

/// Ambient 0.1, diffuse 0.9, a little Phong.
Material matte(const Color& c, float reflection = 0.f);
/// A floor with a checker, three spheres (one a mirror) and two point lights, all scaled by s
/// about the origin: with no absolute epsilon anywhere, the picture must not change.
Scene demoScene(float s);
/// One frame through the scene's camera, tone-mapped to 8-bit sRGB (depth 5).
std::vector<uint8_t> render8(const Scene& sc, int w, int h, int spp, int threads);
/// Image-agreement case: passes when at most 0.1% of pixels differ by more than 1/255 in some
/// channel (catalogue #21's rule, used by every image case).
StabilityCase imageCase(const std::string& id, const std::string& name, const std::vector<uint8_t>& a,
                        const std::vector<uint8_t>& b, bool informative = false);
/// Icosphere of radius r (subdivided icosahedron): a closed mesh with shared vertices and edges.
TriangleMesh icosphere(int levels, float radius, const Vec3& centre);

}  // namespace rf::stability
