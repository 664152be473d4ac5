#pragma once
// Small scenes for the report tests, built with the engine API.
#include <filesystem>
#include <string>

#include "engine/scene/scene.h"

namespace rf::testing {

/// A checkered floor, a matte and a mirror sphere, one point light; glass only if asked.
/// Sphere silhouettes and checker edges make antialiasing matter.
inline Scene edgeScene(bool glass, bool lights = true) {
    Scene sc;
    Material floor;
    floor.color = Color(0.9f);
    floor.color2 = Color(0.1f);
    floor.checkerScale = 0.5f;
    floor.ambient = 0.2f;
    floor.diffuse = 0.8f;
    Material red;
    red.color = Color(0.8f, 0.2f, 0.1f);
    red.specular = 0.5f;
    Material mirror;
    mirror.color = Color(0.9f);
    mirror.diffuse = 0.1f;
    mirror.reflection = 0.8f;
    Material clear;
    clear.color = Color(1.f);
    clear.diffuse = 0.f;
    clear.ambient = 0.f;
    clear.transmission = 0.9f;
    clear.ior = 1.5f;
    sc.materials = {floor, red, mirror};
    if (glass) sc.materials.push_back(clear);  // a material alone makes the scene "have glass"
    sc.geometry.planes.push_back({Vec3(0, 1, 0), 0.f, 0});
    sc.geometry.spheres.push_back({Vec3(-1.2f, 0.7f, 0.f), 0.7f, 1});
    sc.geometry.spheres.push_back({Vec3(0.8f, 0.9f, 0.5f), 0.9f, 2});
    if (glass) sc.geometry.spheres.push_back({Vec3(0.3f, 0.5f, -1.6f), 0.5f, 3});
    if (lights) {
        Light l;
        l.position = Vec3(4, 6, -4);
        sc.lights.push_back(l);
    }
    sc.background = Color(0.1f, 0.15f, 0.3f);
    sc.camera.eye = Vec3(0, 2.f, -5.5f);
    sc.camera.target = Vec3(0, 0.6f, 0);
    sc.camera.fovDeg = 50.f;
    sc.camera.fovHorizontal = true;
    sc.settings.width = 48;
    sc.settings.height = 32;
    sc.settings.spp = 1;
    sc.settings.maxDepth = 5;
    sc.settings.minWeight = 1e-3f;
    sc.build();
    return sc;
}

/// A fresh, empty directory under the test output folder.
inline std::string freshDir(const std::string& name) {
    const std::filesystem::path p = std::filesystem::path(RAYFARM_TEST_OUT) / name;
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p.string();
}

}  // namespace rf::testing
