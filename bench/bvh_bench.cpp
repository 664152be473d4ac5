// Ray throughput of the BVH: primary rays plus one shadow ray per hit, one thread, on a real
// model (default: assimp-testmodels' 121k-triangle 2CylinderEngine) or a synthetic mesh.
//   bvh_bench [MODEL.glb|SCENE.json | --synthetic N] [--size WxH] [--frames N] [--threads N]
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <string>

#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"

#include "bench/bench_util.h"

using namespace rf;

using rf::bench::processCpuSeconds;

namespace {

/// A bumpy sphere of about n triangles: a stand-in when no model is at hand.
Scene syntheticScene(int n) {
    Scene s;
    s.materials.push_back(Material{});
    TriangleMesh m;
    const int rings = std::max(4, static_cast<int>(std::sqrt(n / 2.0)));
    const int segs = rings;
    for (int i = 0; i <= rings; ++i) {
        for (int j = 0; j <= segs; ++j) {
            const float th = kPi * i / rings, ph = 2.f * kPi * j / segs;
            const float r = 1.f + 0.05f * std::sin(7.f * th) * std::cos(9.f * ph);
            m.positions.emplace_back(r * std::sin(th) * std::cos(ph), r * std::cos(th), r * std::sin(th) * std::sin(ph));
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            const uint32_t a = i * (segs + 1) + j, b = a + 1, c = a + segs + 1, d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    s.geometry.meshes.push_back(std::move(m));
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    int synthetic = 0, width = 640, height = 360, frames = 8, threads = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool more = i + 1 < argc;
        if (a == "--synthetic" && more) synthetic = std::atoi(argv[++i]);
        else if (a == "--size" && more) std::sscanf(argv[++i], "%dx%d", &width, &height);
        else if (a == "--frames" && more) frames = std::atoi(argv[++i]);
        else if (a == "--threads" && more) threads = std::atoi(argv[++i]);
        else path = a;
    }
    Scene scene;
    const auto tb0 = std::chrono::steady_clock::now();
    try {
        if (synthetic > 0) {
            scene = syntheticScene(synthetic);
            scene.build();
        } else {
            DiskFileSource fs;
            scene = loadScene(path, fs).scene;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bvh_bench: error: %s\n", e.what());
        return 2;
    }
    const auto tb1 = std::chrono::steady_clock::now();
    scene.build();  // timed alone: the load above includes parsing
    const double buildS = std::chrono::duration<double>(std::chrono::steady_clock::now() - tb1).count();
    const Aabb box = scene.geometry.bounds();
    const Vec3 c = box.center();
    const float radius = 0.5f * glm::length(box.extent());
    if (!(radius > 0.f)) {
        std::fprintf(stderr, "bvh_bench: error: empty scene\n");
        return 2;
    }
    uint64_t primary = 0, shadow = 0, hits = 0;
    std::vector<uint64_t> perFrameHits(frames, 0);
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = processCpuSeconds();
    for (int f = 0; f < frames; ++f) {
        const float ang = 2.f * kPi * f / frames;
        Camera cam;
        cam.eye = c + radius * 2.2f * Vec3(std::sin(ang), 0.35f, std::cos(ang));
        cam.target = c;
        cam.fovDeg = 45.f;
        const Vec3 light = cam.eye + radius * Vec3(0.5f, 1.5f, 0.f);
        const CameraRays rays(cam, width, height);
        std::vector<RayStats> perThread(std::max(1, threads));
        std::vector<uint64_t> rowHits(height, 0);
        parallelFor(height, threads, [&](int y, int t) {
            for (int x = 0; x < width; ++x) {
                const Ray r = rays.generate(x + 0.5f, y + 0.5f);
                ++perThread[t].primary;
                Hit hit;
                if (!scene.geometry.intersect(r, hit)) continue;
                ++rowHits[y];
                const Vec3 p = r.o + hit.t * r.d;
                Ray sr;
                sr.d = glm::normalize(light - p);
                sr.o = p + sr.d * (1e-4f * radius);
                ++perThread[t].shadow;
                scene.geometry.occluded(sr, glm::length(light - sr.o));
            }
        });
        for (const RayStats& s : perThread) {
            primary += s.primary;
            shadow += s.shadow;
        }
        for (uint64_t h : rowHits) perFrameHits[f] += h;
        hits += perFrameHits[f];
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = processCpuSeconds() - cpu0;
    std::printf("bvh_bench: %s: %zu triangles, %zu BVH nodes, build %.3f s (load+build %.3f s)\n",
                synthetic ? "synthetic" : path.c_str(), scene.geometry.triangleCount(),
                scene.geometry.bvh().nodes().size(), buildS, std::chrono::duration<double>(tb1 - tb0).count());
    std::printf("bvh_bench: %d frames %dx%d, %d thread(s): %llu primary + %llu shadow rays, %.1f%% hit, %.3f s, "
                "%.2f Mrays/s (CPU %.3f s: %.2f Mrays per CPU-second)\n",
                frames, width, height, threads, (unsigned long long)primary, (unsigned long long)shadow,
                100.0 * hits / double(primary), s, (primary + shadow) / s * 1e-6, cpu,
                (primary + shadow) / cpu * 1e-6);
    return 0;
}
