// scenes/flight.json rendered at three key times: the moving light's footprint on the floor (the
// brightest floor pixel, directly below a point light over a Lambertian floor) sits where the
// light's keys put it, and its colour follows the colour keys.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/geometry/camera.h"
#include "engine/util/file_source.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::anim {
namespace {

struct Footprint {
    DVec3 world{0.0};
    Color color{0.f};
    bool found = false;
};

/// The brightest pixel whose primary ray ends on the floor (y = 0), projected onto the floor.
Footprint brightestFloorPoint(const Scene& s, const Image& img) {
    const CameraRays cam(s.camera, img.width(), img.height());
    Footprint best;
    float bestSum = -1.f;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            const Ray r = cam.generate(x + 0.5f, y + 0.5f);
            Hit hit;
            if (!s.geometry.intersect(r, hit)) continue;
            const DVec3 o = DVec3(r.o) + s.renderOrigin, d(r.d);
            if (!(d.y < 0.0)) continue;
            const double tFloor = -o.y / d.y;
            if (std::abs(hit.t - tFloor) > 1e-3 * tFloor) continue;  // something else is in front
            const float* p = img.pixel(x, y);
            const float sum = p[0] + p[1] + p[2];
            if (sum > bestSum) {
                bestSum = sum;
                best.world = o + tFloor * d;
                best.color = Color(p[0], p[1], p[2]);
                best.found = true;
            }
        }
    return best;
}

TEST(Flight, LightFootprintFollowsItsKeys) {
    DiskFileSource fs;
    const LoadedScene loadedLoaded = loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/flight.json", fs);
    const Scene& loaded = loadedLoaded.scene;
    const Timeline tl = Timeline::fromScene(loadedLoaded);
    ASSERT_EQ(tl.frameCount(), 97);  // 4 s at 24 fps, both ends
    RenderSettings settings = loaded.settings;
    settings.width = 200;
    settings.height = 120;
    // The light's keyed positions (world xz) at 0, 2 and 4 s, and which colour channel leads.
    struct Key {
        int frame;
        double x, z;
        bool redLeads;
    } keys[] = {{0, -3, -1, true}, {48, 0, 2.5, true}, {96, 3, -1, false}};
    DVec3 previous(1e9);
    for (const Key& k : keys) {
        Scene s = loaded;
        tl.applyFrame(s, k.frame);
        ASSERT_DOUBLE_EQ(tl.frameTime(k.frame), k.frame / 24.0);
        RayStats rays;
        const Image img = renderFrame(s, {s.camera, settings}, k.frame, 0, rays);
        const Footprint f = brightestFloorPoint(s, img);
        const std::string where = "frame " + std::to_string(k.frame);
        bool ok = f.found;
        EXPECT_TRUE(f.found) << where << ": no floor visible";
        // One pixel spans about 0.1 floor units here; allow three.
        const double err = std::hypot(f.world.x - k.x, f.world.z - k.z);
        EXPECT_LT(err, 0.3) << where << ": brightest floor point (" << f.world.x << ", " << f.world.z << "), light keyed at ("
                            << k.x << ", " << k.z << ")";
        ok = ok && err < 0.3;
        EXPECT_EQ(f.color.r > f.color.b, k.redLeads) << where << ": colour " << f.color.r << " " << f.color.g << " " << f.color.b;
        EXPECT_GT(glm::length(f.world - previous), 3.0) << where << ": the footprint did not move";
        previous = f.world;
        if (!ok) {
            const std::string dir = std::string(RAYFARM_TEST_OUT) + "/anim";
            std::filesystem::create_directories(dir);
            writePng(dir + "/flight_frame" + std::to_string(k.frame) + ".png", img.width(), img.height(), toRgb8(img, settings.toneMap));
        }
    }
}

}  // namespace
}  // namespace rf::anim
