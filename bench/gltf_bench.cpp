// glTF model throughput: load time, BVH build time and Mrays/s (primary + one shadow ray per
// hit) for a 640×360 orbit of a model with its default turntable camera and light rig, on one
// thread and on two. Prints figures; not a test.
//   gltf_bench [MODEL.glb] [--size WxH] [--frames N] [--repeat R] [--zoom Z]
// --zoom Z moves the camera Z times closer than the default framing (more of the image hits).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <ctime>

#include "bench/bench_util.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/integrators/render.h"

using namespace rf;

namespace {

double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}


/// The default camera turned about the vertical axis through its target: frame f of n.
Camera orbit(const Camera& base, int f, int n) {
    Camera c = base;
    const double yaw = 2.0 * 3.14159265358979323846 * f / n;
    const glm::dvec3 off = glm::dvec3(base.eye - base.target);
    const double cs = std::cos(yaw), sn = std::sin(yaw);
    c.eye = base.target + Vec3(glm::dvec3(cs * off.x + sn * off.z, off.y, -sn * off.x + cs * off.z));
    return c;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    int width = 640, height = 360, frames = 12, repeat = 3;
    double zoom = 1.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool more = i + 1 < argc;
        if (a == "--size" && more) std::sscanf(argv[++i], "%dx%d", &width, &height);
        else if (a == "--frames" && more) frames = std::max(1, std::atoi(argv[++i]));
        else if (a == "--repeat" && more) repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--zoom" && more) zoom = std::max(0.01, std::atof(argv[++i]));
        else path = a;
    }
    try {
        // Load (parse, check, convert) without the BVH, best of `repeat`; then the build alone.
        double loadS = 1e30, buildS = 1e30, loadCpu = 1e30, buildCpu = 1e30;
        Scene scene;
        for (int r = 0; r < repeat; ++r) {
            DiskFileSource fs;
            const double c0 = rf::bench::processCpuSeconds();
            const auto t0 = std::chrono::steady_clock::now();
            Scene s;
            loadGltfModel(s, path, DMat4(1.0), fs);
            const double c1 = rf::bench::processCpuSeconds();
            const auto t1 = std::chrono::steady_clock::now();
            s.build();
            const double c2 = rf::bench::processCpuSeconds();
            const auto t2 = std::chrono::steady_clock::now();
            loadS = std::min(loadS, seconds(t0, t1));
            buildS = std::min(buildS, seconds(t1, t2));
            loadCpu = std::min(loadCpu, c1 - c0);
            buildCpu = std::min(buildCpu, c2 - c1);
        }
        {
            DiskFileSource fs;
            scene = loadGltfScene(path, fs);  // with the turntable camera and the default rig
        }
        scene.camera.eye = scene.camera.target + Vec3(glm::dvec3(scene.camera.eye - scene.camera.target) / zoom);
        RenderSettings settings = scene.settings;
        settings.width = width;
        settings.height = height;
        settings.maxDepth = 1;  // primary rays and their shadow rays only
        const auto bounceSlot = std::make_shared<SceneCacheSlot>();  // the run's, as a render job keeps it
        std::printf("model        %s\n", path.c_str());
        std::printf("cores        %d hardware threads; load the machine lightly for wall-clock figures\n", hardwareThreads());
        std::printf(
            "triangles    %zu   lights %zu (shadowing: %d)\n", scene.geometry.triangleCount(), scene.lights.size(),
            int(std::count_if(scene.lights.begin(), scene.lights.end(), [](const Light& l) { return l.castShadows; })));
        std::printf("load         %.3f s wall, %.3f s CPU (parse + convert, 1 thread, best of %d)\n", loadS, loadCpu, repeat);
        std::printf("bvh build    %.3f s wall, %.3f s CPU (1 thread, best of %d)\n", buildS, buildCpu, repeat);
        {
            // How much of the orbit the model covers: misses are cheap, so say it with the rate.
            RayStats st;
            const Image img = renderFrame(scene, {scene.camera, settings, bounceSlot}, 0, 1, st);
            size_t covered = 0;
            for (int y = 0; y < img.height(); ++y)
                for (int x = 0; x < img.width(); ++x) {
                    const float* p = img.pixel(x, y);
                    covered += !(p[0] == scene.background.r && p[1] == scene.background.g && p[2] == scene.background.b);
                }
            std::printf("coverage     %.1f%% of the pixels of frame 0 show the model\n", 100.0 * covered / (double(width) * height));
        }
        for (int threads : {1, 2}) {
            RayStats stats;
            const double c0 = rf::bench::processCpuSeconds();
            const auto t0 = std::chrono::steady_clock::now();
            for (int f = 0; f < frames; ++f)
                renderFrame(scene, {orbit(scene.camera, f, frames), settings, bounceSlot}, f, threads, stats);
            const double s = seconds(t0, std::chrono::steady_clock::now());
            const double cpu = rf::bench::processCpuSeconds() - c0;
            std::printf("%d thread%s   %.2f Mrays/s wall, %.2f Mrays per CPU-second  (%llu primary + %llu shadow rays, %d frames "
                        "%dx%d in %.2f s, %.1f fps)\n",
                        threads, threads > 1 ? "s" : " ", stats.total() / s / 1e6, stats.total() / cpu / 1e6,
                        (unsigned long long)stats.primary, (unsigned long long)stats.shadow, frames, width, height, s, frames / s);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gltf_bench: %s\n", e.what());
        return 2;
    }
    return 0;
}
