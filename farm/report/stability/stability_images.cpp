// Image cases of the catalogue: the same picture rendered two ways (scaled, translated, from
// farther away) must agree, and lit surfaces must stay lit at range.
#include <cmath>
#include <sstream>

#include "engine/util/image.h"
#include "engine/load/json_scene_loader.h"
#include "farm/report/stability/stability_cases.h"
#include "farm/report/stability/stability_scenes.h"

namespace rf::stability {

namespace {

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
    return loadJsonScene(name, fs).scene;
}
}  // namespace

Scene translatedScene(double dx) { return loadFromText("scene.json", jsonScene(dx)); }

void translatedModel(std::vector<StabilityCase>& out, int threads) {
    const Scene origin = loadFromText("origin.json", jsonScene(0.0));
    const Scene far = loadFromText("far.json", jsonScene(6.4e6));
    const std::vector<uint8_t> ref = render8(origin, kW, kH, 1, threads);
    out.push_back(imageCase("22", "scene file translated to x = 6.4e6 (loader rebases to the camera)",
                            render8(far, kW, kH, 1, threads), ref));
    // The same scene with float world coordinates (no rebasing): float spacing at 6.4e6 is 0.5.
    Scene naive = origin;
    const Vec3 shift(6.4e6f, 0.f, 0.f);
    for (Sphere& s : naive.geometry.spheres) s.center += shift;
    for (Plane& p : naive.geometry.planes) p.d -= glm::dot(p.n, shift);
    for (Light& l : naive.lights) l.position += shift;
    naive.camera.eye += shift;
    naive.camera.target += shift;
    naive.renderOrigin -= DVec3(shift);  // world positions unchanged, only the float frame moves
    naive.build();
    out.push_back(imageCase("22", "the same at x = 6.4e6 in float world coordinates (no rebasing)",
                            render8(naive, kW, kH, 1, threads), ref, true));
}

void distanceInvariance(std::vector<StabilityCase>& out, int threads) {
    // The catalogue's pair, 10 and 1000, with flat (ambient-only) shading: the silhouette alone,
    // which the scaled field of view keeps on the same pixels (angular radius asin(1/d), filling
    // 0.6 of the half-height).
    auto flat = [](float dist) {
        Scene sc;
        Material m;
        m.color = Color(0.9f, 0.6f, 0.3f);
        m.ambient = 1.f;
        m.diffuse = 0.f;
        m.specular = 0.f;
        sc.materials = {m};
        sc.background = Color(0.1f);
        sc.geometry.spheres.push_back({Vec3(0.2f, -0.1f, 0.f), 1.f, 0});
        sc.camera.eye = Vec3(0.2f, -0.1f, dist);
        sc.camera.target = Vec3(0.2f, -0.1f, 0.f);
        sc.camera.fovDeg = float(glm::degrees(2.0 * std::atan(std::tan(std::asin(1.0 / dist)) / 0.6)));
        sc.build();
        return sc;
    };
    out.push_back(imageCase("3", "unit sphere, flat shaded, from distance 1000 against 10, field of view scaled",
                            render8(flat(1000.f), 96, 64, 1, threads), render8(flat(10.f), 96, 64, 1, threads)));
    auto lit = [](float dist) {
        Scene sc;
        sc.materials = {matte(Color(0.8f, 0.3f, 0.2f))};
        sc.geometry.spheres.push_back({Vec3(0.f), 1.f, 0});
        Light l;
        l.position = Vec3(3, 4, 5);
        sc.lights = {l};
        sc.camera.eye = Vec3(0, 0, dist);
        sc.camera.target = Vec3(0.f);
        sc.camera.fovDeg = float(2.0 * std::atan(1.5 / dist) * 180.0 / 3.14159265358979);
        sc.build();
        return sc;
    };
    // Lit, at 10 the perspective itself differs (a 5.7° cone onto the sphere, not 0.06°): the
    // lit pair is 1000 and 1e5, where only precision can differ.
    out.push_back(imageCase("3", "unit sphere, lit, from distance 1e5 against 1000, field of view scaled",
                            render8(lit(1e5f), kW, kH, 1, threads), render8(lit(1000.f), kW, kH, 1, threads)));
}

void selfShadowAtRange(std::vector<StabilityCase>& out, int threads) {
    Scene sc;
    Material m = matte(Color(1.f));
    m.ambient = 0.f;
    m.specular = 0.f;
    sc.materials = {m};
    sc.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
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
    sc.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
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

void scaleSweep(std::vector<StabilityCase>& out, int threads) {
    const std::vector<uint8_t> ref = render8(demoScene(1.f), kW, kH, 1, threads);
    for (float s : {1e-4f, 1e5f})
        out.push_back(imageCase("21", "whole scene scaled by " + formatValue("%g", s) + " against scale 1",
                                render8(demoScene(s), kW, kH, 1, threads), ref));
}

std::vector<StabilityCase> engineCases(int threads) {
    std::vector<StabilityCase> out;
    farSmallSphere(out);
    distanceInvariance(out, threads);
    triangleSeam(out);
    watertight(out);
    selfShadowAtRange(out, threads);
    flatQuads(out, threads);
    thinGap(out);
    lightJustAbovePlane(out, threads);
    scaleSweep(out, threads);
    translatedModel(out, threads);
    tilingIndependence(out, threads);
    dimLightScene(out, threads);
    smoothGlassMesh(out, threads);
    return out;
}

}  // namespace rf::stability
