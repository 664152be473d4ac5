// Times the Whitted orbit: scenes/whitted.json, every frame of its timeline rendered on all local
// cores, as bench/bench_whitted.sh runs it next to POV-Ray. Prints frames per second.
//   whitted_bench [SCENE] [--size WxH] [--frames N] [--threads N] [--depth N] [--out DIR]
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "engine/util/errors.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

#include "bench/bench_util.h"

using namespace rf;

using rf::bench::processCpuSeconds;

int main(int argc, char** argv) {
    std::string path = "scenes/whitted.json", outDir;
    int width = 640, height = 360, frames = 31, threads = 0, depth = 5;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool more = i + 1 < argc;
        if (a == "--size" && more) std::sscanf(argv[++i], "%dx%d", &width, &height);
        else if (a == "--frames" && more) frames = std::atoi(argv[++i]);
        else if (a == "--threads" && more) threads = std::atoi(argv[++i]);
        else if (a == "--depth" && more) depth = std::atoi(argv[++i]);
        else if (a == "--out" && more) outDir = argv[++i];
        else path = a;
    }
    try {
        DiskFileSource fs;
        const auto tLoad = std::chrono::steady_clock::now();
        LoadedScene loaded = loadScene(path, fs);
        Scene& scene = loaded.scene;
        const anim::Timeline timeline = anim::Timeline::fromScene(loaded);
        // Until the scene's timeline carries the orbit, drive POV-Ray's camera path ourselves:
        // eye (8 sin 2πc, 3, −8 cos 2πc) with c = i / (frames − 1), as whitted.pov's clock.
        const bool ownOrbit = timeline.frameCount() < frames;
        RenderSettings settings = scene.settings;
        settings.width = width;
        settings.height = height;
        settings.spp = 1;
        settings.maxDepth = depth;
        if (threads <= 0) threads = hardwareThreads();
        RayStats rays;
        const auto bounceSlot = std::make_shared<SceneCacheSlot>();  // the run's, as a render job keeps it
        const auto t0 = std::chrono::steady_clock::now();
        const double cpu0 = processCpuSeconds();
        for (int i = 0; i < frames; ++i) {
            if (ownOrbit) {
                const double c = frames > 1 ? double(i) / (frames - 1) : 0.0;
                const DVec3 eye(8.0 * std::sin(2.0 * M_PI * c), 3.0, -8.0 * std::cos(2.0 * M_PI * c));
                scene.camera.eye = Vec3(eye - scene.renderOrigin);
            } else {
                timeline.applyFrame(scene, i);
            }
            const Image img = renderFrame(scene, {scene.camera, settings, bounceSlot}, i, threads, rays);
            if (!outDir.empty()) {
                char name[64];
                std::snprintf(name, sizeof name, "/frame_%03d.png", i);
                writePng(outDir + name, img.width(), img.height(), toRgb8(img, settings.toneMap));
            }
        }
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double loadS = std::chrono::duration<double>(t0 - tLoad).count();
        const double cpu = processCpuSeconds() - cpu0;
        std::printf("rayfarm: %d frames %dx%d depth %d, %d threads, orbit from %s: %.3f s (load %.3f s), %.2f fps, "
                    "%.1f Mrays/s (%llu rays); CPU %.3f s, %.1f ms CPU per frame\n",
                    frames, width, height, depth, threads, ownOrbit ? "the bench" : "the scene timeline", s, loadS,
                    frames / s, rays.total() / s * 1e-6, static_cast<unsigned long long>(rays.total()), cpu, 1e3 * cpu / frames);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "whitted_bench: error: %s\n", e.what());
        return 2;
    }
    return 0;
}
