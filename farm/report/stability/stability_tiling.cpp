// A pixel is a function of (scene, frame, pixel, sample) only: the tile it was traced in, the
// camera-ray packets and each thread's blocker cache may make it faster, never different.
#include <cstring>

#include "engine/lights/exposure.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "farm/report/stability/stability_cases.h"
#include "farm/report/stability/stability_scenes.h"

namespace rf::stability {

namespace {

/// A floor of two big triangles just above y = 0 under an icosphere of 320 triangles and a point light.
Scene meshFloorScene() {
    Scene sc;
    Material m = matte(Color(0.8f));
    sc.materials = {m};
    TriangleMesh floor;
    floor.positions = {Vec3(-50, 1e-3f, -50), Vec3(50, 1e-3f, -50), Vec3(50, 1e-3f, 50), Vec3(-50, 1e-3f, 50)};
    floor.indices = {0, 2, 1, 0, 3, 2};
    sc.geometry.meshes.push_back(floor);
    sc.geometry.meshes.push_back(icosphere(2, 1.f, Vec3(0.f, 1.2f, 0.f)));
    Light l;
    l.position = Vec3(3.f, 6.f, 2.f);
    sc.lights = {l};
    sc.background = Color(0.05f);
    sc.camera.eye = Vec3(0.f, 3.f, 8.f);
    sc.camera.target = Vec3(0.f, 0.8f, 0.f);
    sc.build();
    return sc;
}

/// Pixels (of w × h) in which some variant's floats differ from tile 32 with packets and cache.
int variantsDiffering(const Scene& sc, int w, int h, int threads, int& variants) {
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.spp = 4;
    RayStats rays;
    const Image ref = renderFrame(sc, {sc.camera, s}, 0, threads, rays);
    std::vector<bool> bad(size_t(w) * h, false);
    variants = 0;
    for (int tile : {1, 7, 16, 32, 128})
        for (int mode = 0; mode < 3; ++mode) {  // packets and cache; no packets; no cache
            s.tileSize = tile;
            s.packets = mode != 1;
            s.blockerCache = mode != 2;
            const Image img = renderFrame(sc, {sc.camera, s}, 0, threads, rays);
            ++variants;
            for (size_t i = 0; i < bad.size(); ++i) bad[i] = bad[i] || std::memcmp(img.data() + 3 * i, ref.data() + 3 * i, 3 * sizeof(float)) != 0;
        }
    int n = 0;
    for (bool b : bad) n += b;
    return n;
}

}  // namespace

void tilingIndependence(std::vector<StabilityCase>& out, int threads) {
    struct Named {
        std::string name;
        Scene scene;
    };
    const Named scenes[] = {{"spheres, plane, mirrors (scene-file model)", demoScene(1.f)},
                            {"mesh floor at y = 1e-3 under a mesh ball", meshFloorScene()}};
    for (const Named& n : scenes) {
        int variants = 0;
        const int bad = variantsDiffering(n.scene, kW, kH, threads, variants);
        StabilityCase c{"tiles", n.name + ": tile sizes 1, 7, 16, 32, 128 × packets, blocker cache on/off", "",
                        double(bad), 0.0, "pixels differ", bad == 0, false};
        c.measured = std::to_string(bad) + " of " + std::to_string(kW * kH) + " pixels differ (floats, 4 spp) across " +
                     std::to_string(variants) + " variants";
        out.push_back(c);
    }
}

}  // namespace rf::stability

namespace rf::stability {

void dimLightScene(std::vector<StabilityCase>& out, int threads) {
    // A floor and a ball under one 10 cd point lamp (photometric, as glTF gives it: 10/683 W/sr),
    // glTF material, metered as auto exposure does (unpruned), then rendered at the default
    // --min-weight: it must match the unpruned picture at that EV and not be black.
    Scene sc;
    Material m;
    m.gltfPbr = true;
    m.color = Color(0.8f);
    m.roughness = 0.6f;
    m.metallic = 0.f;
    sc.materials = {m};
    sc.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    sc.geometry.spheres.push_back({Vec3(0.f, 0.6f, 0.f), 0.6f, 0});
    Light l;
    l.position = Vec3(1.2f, 2.2f, 0.8f);
    l.intensity = 10.f / kLumensPerWatt;
    l.attenuation = Vec3(0.f, 0.f, 1.f);
    l.photometric = true;
    sc.lights = {l};
    sc.background = Color(0.f);
    sc.camera.eye = Vec3(0.f, 2.2f, 4.2f);
    sc.camera.target = Vec3(0.f, 0.5f, 0.f);
    sc.build();
    RenderSettings s;
    s.width = kW;
    s.height = kH;
    s.toneMap = ToneMap::PbrNeutral;
    s.minWeight = 0.f;
    RayStats rays;
    ExposureMeter meter;
    meter.add(renderFrame(sc, {sc.camera, s}, 0, threads, rays));
    s.exposure = meter.ev();
    const std::vector<uint8_t> full = toRgb8(renderFrame(sc, {sc.camera, s}, 0, threads, rays), s);
    s.minWeight = RenderSettings{}.minWeight;
    const std::vector<uint8_t> pruned = toRgb8(renderFrame(sc, {sc.camera, s}, 0, threads, rays), s);
    double mean = 0.0;
    for (uint8_t v : pruned) mean += v;
    mean /= double(pruned.size());
    StabilityCase c = imageCase("units", "one 10 cd lamp, default --min-weight against unpruned, at the metered EV", pruned, full);
    c.measured += ", EV " + formatValue("%+.2f", s.exposure) + ", mean level " + formatValue("%.1f", mean);
    c.pass = c.pass && mean > 20.0;
    out.push_back(c);
}

}  // namespace rf::stability
