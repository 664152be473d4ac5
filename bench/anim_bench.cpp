// Timeline costs per frame: what a static scene, a camera orbit and an animated mesh pay in
// Timeline::apply, and what Timeline::fromScene costs to set up. Prints figures; not a test.
//   anim_bench [--grid N]   (an N×N vertex grid hangs on the animated node; default 512)
//   anim_bench --model FILE...   (each model's own timeline: pose, skin and refit per frame)
//   anim_bench --rule FILE [--frames N] [--size WxH]   (the rebuild rule measured: for N frames
//       spread over the film, render time with the refitted tree against a fresh build, beside
//       the refit's SAH ratio; also the ratios refitting from the rest pose would give)
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <string>

#include <glm/gtc/quaternion.hpp>

#include "engine/util/file_source.h"
#include "engine/load/scene_loader.h"
#include "anim/gltf_animation.h"
#include "engine/integrators/render.h"
#include "anim/timeline.h"

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
    s.geometry.models.push_back(g);
    s.geometry.meshes.push_back(std::move(m));
    Light l;
    l.position = Vec3(2, 3, 2);
    s.lights.push_back(l);
    s.build();
    return s;
}

void measure(const char* what, LoadedScene loaded, size_t vertices) {
    Scene& s = loaded.scene;
    const double t0 = now();
    const anim::Timeline tl = anim::Timeline::fromScene(loaded);
    const double setup = now() - t0;
    const int frames = std::min(tl.frameCount(), 120);
    double pose = 0.0, tree = 0.0, ratio = 0.0;
    int rebuilt = 0, anchors = 0;
    const double t1 = now();
    for (int f = 0; f < frames; ++f) {
        tl.applyFrame(s, f);
        const SceneGeometry::UpdateCost& c = s.geometry.lastUpdateCost();
        pose += c.poseS;
        tree += c.treeS;
        anchors += c.anchorsBuilt;
        ratio = std::max(ratio, c.sahRatio);
        rebuilt += s.geometry.lastRefitRebuilt();
    }
    const double per = (now() - t1) / frames;
    std::printf("%-34s %9zu vertices  fromScene %8.3f ms  apply %9.4f ms/frame  (%d frames timed, %s)\n", what, vertices,
                1e3 * setup, 1e3 * per, frames, tl.animatesGeometry() ? "geometry moves" : "no geometry work");
    if (tl.animatesGeometry())
        std::printf(
            "%-34s   of which pose (morph, skin) %.3f ms/frame, trees %.3f ms/frame (%d anchor trees built, "
            "%d of %d frames rebuilt, largest refit SAH ratio %.3f, rebuild above %.2f)\n",
            "", 1e3 * pose / frames, 1e3 * tree / frames, anchors, rebuilt, frames, ratio,
            SceneGeometry::kRebuildGrowth);
}


double cpuNow() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// One frame's render cost on one thread at the scene's settings: CPU seconds (a shared machine
/// stretches wall time far more than CPU time), best of 3.
double renderSeconds(const Scene& s, int w, int h) {
    RenderSettings st = s.settings;
    st.width = w;
    st.height = h;
    st.autoExposure = false;
    // One view for the three: the bounce cache, built in the first, is found by the others, so the
    // best of three times the tree, not the cache.
    const RenderView view{s.camera, st};
    double best = 1e30;
    for (int k = 0; k < 3; ++k) {
        RayStats rays;
        const double t0 = cpuNow();
        (void)renderFrame(s, view, 0, 1, rays);
        best = std::min(best, cpuNow() - t0);
    }
    return best;
}

/// The rebuild rule measured on a model's film: at each sampled frame, the tree the anchors give
/// refitted (rebuildGrowth infinite) against the same pose built afresh (rebuildGrowth 0): their
/// SAH ratio and render times; and the ratio a refit of the rest pose's tree would have had.
void measureRule(const std::string& file, int samples, int w, int h) {
    DiskFileSource fs;
    const LoadedScene model = loadScene(file, fs);
    const Scene& loaded = model.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(model);
    std::printf("%s: %d frames, %dx%d, %d spp, one thread; per sampled frame: SAH ratio of the refit (anchor | rest pose), "
                "render ms refit vs fresh build, pose/refit/rebuild ms\n",
                file.c_str(), tl.frameCount(), w, h, loaded.settings.spp);
    double sumRefit = 0.0, sumFresh = 0.0, sumRest = 0.0;
    for (int i = 0; i < samples; ++i) {
        const int f = int((long long)i * tl.frameCount() / samples);
        Scene refit = loaded, fresh = loaded, rest = loaded;
        refit.geometry.rebuildGrowth = 1e30;
        fresh.geometry.rebuildGrowth = 0.0;
        rest.geometry.rebuildGrowth = 1e30;
        tl.applyFrame(refit, f);  // builds the anchor's tree first: timed apart below
        tl.applyFrame(refit, f);
        const SceneGeometry::UpdateCost c = refit.geometry.lastUpdateCost();
        tl.applyFrame(fresh, f);
        tl.applyFrame(fresh, f);
        const SceneGeometry::UpdateCost cf = fresh.geometry.lastUpdateCost();
        // The rest pose's tree refitted: the frame's pose without an anchor.
        tl.applyFrame(rest, f);
        double restRatio = 0.0;
        for (size_t m = 0; m < rest.geometry.models.size(); ++m) {
            if (rest.geometry.models[m].animations.empty()) continue;
            const anim::GltfAnimationPlayer p(rest.geometry.models[m], int(m), 0, true);
            std::vector<DMat4> nodes;
            std::vector<std::vector<double>> weights;
            p.pose(rest.geometry.models[m], tl.frameTime(f), nodes, weights);
            rest.geometry.applyNodeTransforms(int(m), nodes, weights);
            restRatio = std::max(restRatio, rest.geometry.lastUpdateCost().sahRatio);
        }
        rest.camera = refit.camera;
        const double tr = renderSeconds(refit, w, h), tf = renderSeconds(fresh, w, h), tq = renderSeconds(rest, w, h);
        sumRefit += tr;
        sumFresh += tf;
        sumRest += tq;
        std::printf("  frame %4d: SAH ratio %.3f, render %.1f ms (%+.1f%%) | rest pose refitted: ratio %.3f, %.1f ms (%+.1f%%) | fresh %.1f ms"
                    " | pose %.1f, refit %.1f, rebuild %.1f ms\n",
                    f, c.sahRatio, 1e3 * tr, 100.0 * (tr / tf - 1.0), restRatio, 1e3 * tq, 100.0 * (tq / tf - 1.0), 1e3 * tf,
                    1e3 * c.poseS, 1e3 * c.treeS, 1e3 * cf.treeS);
    }
    std::printf("  over the sampled frames (CPU ms a frame): anchor refitted %.1f (%+.1f%%), rest pose refitted %.1f (%+.1f%%), "
                "fresh %.1f\n",
                1e3 * sumRefit / samples, 100.0 * (sumRefit / sumFresh - 1.0), 1e3 * sumRest / samples,
                100.0 * (sumRest / sumFresh - 1.0), 1e3 * sumFresh / samples);
}

}  // namespace

int main(int argc, char** argv) {
    int n = 512;
    for (int i = 1; i + 1 < argc; ++i)
        if (!std::strcmp(argv[i], "--grid")) n = std::max(2, std::atoi(argv[i + 1]));
    for (int i = 1; i + 1 < argc; ++i)
        if (!std::strcmp(argv[i], "--rule")) {
            int samples = 12, w = 640, h = 360;
            for (int k = 1; k + 1 < argc; ++k) {
                if (!std::strcmp(argv[k], "--frames")) samples = std::max(1, std::atoi(argv[k + 1]));
                if (!std::strcmp(argv[k], "--size")) std::sscanf(argv[k + 1], "%dx%d", &w, &h);
            }
            measureRule(argv[i + 1], samples, w, h);
            return 0;
        }
    DiskFileSource fs;
    // --model FILE...: each file's own timeline, posed frame by frame (pose + skin + refit).
    bool models = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--model")) {
            models = true;
            continue;
        }
        if (!models) continue;
        LoadedScene s = loadScene(argv[i], fs);
        size_t v = 0;
        for (const TriangleMesh& m : s.scene.geometry.meshes) v += m.positions.size();
        measure(argv[i], std::move(s), v);
    }
    if (models) return 0;
    measure("whitted.json (camera orbit)", loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/whitted.json", fs), 0);
    measure("flight.json (camera + light keys)", loadScene(std::string(RAYFARM_SOURCE_DIR) + "/scenes/flight.json", fs), 0);
    const size_t v = size_t(n) * size_t(n);
    measure("static grid model (turntable)", {gridModel(n, false), {}}, v);
    measure("animated grid model (turntable)", {gridModel(n, true), {}}, v);
    // The engine's share of that: the BVH refit alone (applyNodeTransforms ends with it).
    Scene g = gridModel(n, true);
    const double t0 = now();
    for (int i = 0; i < 10; ++i) g.geometry.refit();
    std::printf("%-34s %9zu vertices  SceneGeometry::refit alone %9.4f ms\n", "animated grid model", v,
                1e3 * (now() - t0) / 10);
    return 0;
}
