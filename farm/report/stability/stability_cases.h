#pragma once
/// The catalogue's cases the engine can measure alone, each defined once: the engine's tests
/// assert them and `rayfarm report --stability` tabulates them. Each function appends its
/// rows (a case may add an informative naive contrast); threads: 0 for all cores.
#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "farm/report/stability/stability_case.h"

namespace rf::stability {

/// #1: a sphere of radius 0.1 hit by rays from x = −400, −1e4, −1e7 (relative t error).
void farSmallSphere(std::vector<StabilityCase>& out);
/// #3: a unit sphere seen from far away and farther with the field of view scaled to match:
/// flat-shaded from 10 and 1000, lit from 1000 and 1e5 (% of pixels off by more than 1/255).
void distanceInvariance(std::vector<StabilityCase>& out, int threads);
/// #4: a ray onto the shared diagonal of two triangles.
void triangleSeam(std::vector<StabilityCase>& out);
/// #5: a closed icosphere: a grid of rays plus rays at every vertex and edge; none may miss.
void watertight(std::vector<StabilityCase>& out);
/// #11: a lit plane seen from 1e6 away has no self-shadowed pixel.
void selfShadowAtRange(std::vector<StabilityCase>& out, int threads);
/// The bound flatQuads holds a quad's speckle to: the standard deviation of its pixels' 8-bit
/// red value (the picture is uniform grey; one self-shadowed sample of four moves a pixel by
/// dozens of levels).
constexpr double kQuadSpeckleBound = 0.5;
/// #11 on triangles: standard deviation of the 8-bit levels of a uniformly lit flat quad (two
/// triangles, two directional lights, one grazing) centred at (0, 0, z) and turned by tiltDeg
/// about x, filling a 48×48 frame at 4 spp.
double flatQuadSpeckle(float z, float tiltDeg, int threads);
/// #11 on triangles: flatQuadSpeckle at z = 1e-3, 1e3, 1e5, tilted 0°, 30° and 60°.
void flatQuads(std::vector<StabilityCase>& out, int threads);
/// #12: spheres of radius 1 and 1 + 4e-5: a ray spawned inward from the outer one stops at the
/// inner one, within 1e-6 of the gap.
void thinGap(std::vector<StabilityCase>& out);
/// #14: a point light 1e-3 above a plane still lights it.
void lightJustAbovePlane(std::vector<StabilityCase>& out, int threads);
/// #21: the whole scene scaled by 1e-4 and by 1e5 against scale 1.
void scaleSweep(std::vector<StabilityCase>& out, int threads);
/// #22: a scene file translated to x = 6.4e6 against the same at the origin, plus the naive
/// contrast in float world coordinates (informative).
void translatedModel(std::vector<StabilityCase>& out, int threads);

/// A pixel depends on (scene, frame, pixel, sample) only: two scenes rendered at tile sizes 1, 7,
/// 16, 32, 128, each with packets and the blocker cache, without packets, without the cache;
/// the pixels whose floats differ from one reference (none may).
void tilingIndependence(std::vector<StabilityCase>& out, int threads);

/// Light units: a floor and ball under one 10 cd lamp, metered unpruned, then rendered at the
/// default --min-weight: the same picture as unpruned, and lit (mean level above 20).
void dimLightScene(std::vector<StabilityCase>& out, int threads);

/// Smooth glass: a 64 × 32 smooth UV sphere mesh of glass over a checker floor against the
/// analytic sphere (RMS difference in 8-bit levels, at most 4).
void smoothGlassMesh(std::vector<StabilityCase>& out, int threads);

/// The scene file translatedModel loads, its positions moved by dx along x (for tests of the
/// loader's rebasing itself).
Scene translatedScene(double dx);

/// Every case above, in catalogue order.
std::vector<StabilityCase> engineCases(int threads);

}  // namespace rf::stability
