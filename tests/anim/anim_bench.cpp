// Timeline costs per frame: what a static scene, a camera orbit and an animated mesh pay in
// Timeline::apply, and what Timeline::fromScene costs to set up. Prints figures; not a test.
//   anim_bench [--grid N]   (an N×N vertex grid hangs on the animated node; default 512)
//   anim_bench --model FILE...   (each model's own timeline: pose, skin and refit per frame)
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "file_source.h"
#include "scene_loader.h"
#include "timeline.h"

using namespace rf;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// A bare "model" built in code: an N×N grid on node 0; animated: node 0 turns about y.
Scene gridModel(int n, bool animated) {
    Scene s;
    s.sourcePath = animated ? "synthetic_animated.gltf" : "synthetic_static.gltf";
    TriangleMesh m;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) m.positions.emplace_back(float(i) / (n - 1) - 0.5f, 0.1f * std::sin(0.1f * float(i + j)), float(j) / (n - 1) - 0.5f);
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const uint32_t a = uint32_t(j * n + i), b = a + 1, c = a + uint32_t(n), d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    SceneGraph g;
    g.source = s.sourcePath;
    g.nodes.resize(1);
    if (animated) {
        m.model = 0;
        m.node = 0;
        m.objectPositions = m.positions;
        Animation a;
        AnimSampler smp;
        smp.components = 4;
        smp.times = {0.f, 2.f};
        const DQuat q = glm::angleAxis(glm::radians(170.0), DVec3(0, 1, 0));
        smp.values = {0, 0, 0, 1, float(q.x), float(q.y), float(q.z), float(q.w)};
        a.samplers.push_back(smp);
        a.channels.push_back({0, 0, AnimPath::Rotation});
        g.animations.push_back(a);
    }
    s.models.push_back(g);
    s.meshes.push_back(std::move(m));
    Light l;
    l.position = Vec3(2, 3, 2);
    s.lights.push_back(l);
    s.build();
    return s;
}

void measure(const char* what, Scene s, size_t vertices) {
    const double t0 = now();
    const anim::Timeline tl = anim::Timeline::fromScene(s);
    const double setup = now() - t0;
    const int frames = std::min(tl.frameCount(), 120);
    const double t1 = now();
    for (int f = 0; f < frames; ++f) tl.applyFrame(s, f);
    const double per = (now() - t1) / frames;
    std::printf("%-34s %9zu vertices  fromScene %8.3f ms  apply %9.4f ms/frame  (%d frames timed, %s)\n", what, vertices,
                1e3 * setup, 1e3 * per, frames, tl.animatesGeometry() ? "geometry moves" : "no geometry work");
}

}  // namespace

int main(int argc, char** argv) {
    int n = 512;
    for (int i = 1; i + 1 < argc; ++i)
        if (!std::strcmp(argv[i], "--grid")) n = std::max(2, std::atoi(argv[i + 1]));
    DiskFileSource fs;
    // --model FILE...: each file's own timeline, posed frame by frame (pose + skin + refit).
    bool models = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--model")) {
            models = true;
            continue;
        }
        if (!models) continue;
        Scene s = loadScene(argv[i], fs);
        size_t v = 0;
        for (const TriangleMesh& m : s.meshes) v += m.positions.size();
        measure(argv[i], std::move(s), v);
    }
    if (models) return 0;
    measure("whitted.json (camera orbit)", loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", fs), 0);
    measure("flight.json (camera + light keys)", loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/flight.json", fs), 0);
    const size_t v = size_t(n) * size_t(n);
    measure("static grid model (turntable)", gridModel(n, false), v);
    measure("animated grid model (turntable)", gridModel(n, true), v);
    // The engine's share of that: the BVH refit alone (applyNodeTransforms ends with it).
    Scene g = gridModel(n, true);
    const double t0 = now();
    for (int i = 0; i < 10; ++i) g.refit();
    std::printf("%-34s %9zu vertices  Scene::refit alone %9.4f ms\n", "animated grid model", v, 1e3 * (now() - t0) / 10);
    return 0;
}
