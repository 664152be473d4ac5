// Equal-work reference for traversal speed: renders a rayfarm scene file's orbit with Embree 3
// instead of rayfarm's BVH. Same triangles (loaded and placed by rayfarm), same cameras (the
// scene's timeline), same primary rays (rf::CameraRays), one closest-hit ray per pixel and one
// shadow ray per hit towards the scene's first point light, shaded with a plain Lambert term.
// bench/bench_embree.sh times this whole process next to `rayfarm render --no-frames`.
// --tracer rayfarm runs the same loop on rayfarm's own SceneGeometry::intersect and SceneGeometry::occluded
// (no blocker cache) in place of rtcIntersect1/rtcOccluded1: the traversal alone, on the same
// rays with the same shading, without rayfarm's renderer, film and encoder around it.
// Prints figures; not a test. Built only when CMake finds Embree 3.
//   embree_bench SCENE.json [--threads N] [--tracer embree|rayfarm] [--out frame0.png]
#include <embree3/rtcore.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_util.h"
#include "engine/util/image.h"
#include "engine/integrators/render.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

using namespace rf;

namespace {

/// All triangle meshes of the scene, as one Embree geometry in render space.
RTCScene buildEmbreeScene(RTCDevice device, const Scene& scene) {
    size_t nv = 0, nt = 0;
    for (const TriangleMesh& m : scene.geometry.meshes) {
        nv += m.positions.size();
        nt += m.triangleCount();
    }
    RTCScene es = rtcNewScene(device);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ix = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    size_t vb = 0, ib = 0;
    for (const TriangleMesh& m : scene.geometry.meshes) {
        for (const Vec3& p : m.positions) {
            v[3 * vb] = p.x;
            v[3 * vb + 1] = p.y;
            v[3 * vb + 2] = p.z;
            ++vb;
        }
        const unsigned base = static_cast<unsigned>(vb - m.positions.size());
        for (uint32_t i : m.indices) ix[ib++] = base + i;
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(es, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(es);
    return es;
}

/// The harness's shading of a hit at distance t with geometric normal ng: ambient 0.05 plus the
/// unattenuated cosine to the light unless blocked(origin, direction, distance) says a shadow
/// ray from just off the surface meets something first.
template <typename Blocked>
float lambert(const Ray& r, float t, Vec3 ng, const Vec3& light, Blocked&& blocked) {
    const Vec3 p = r.o + t * r.d;
    Vec3 n = glm::normalize(ng);
    if (glm::dot(n, r.d) > 0.f) n = -n;
    const Vec3 toL = light - p;
    const float dist = glm::length(toL);
    const Vec3 l = toL / dist;
    const float cosL = glm::dot(n, l);
    if (cosL <= 0.f) return 0.05f;
    const Vec3 o = p + 1e-4f * glm::max(1.f, glm::length(p)) * n;  // off the surface, scaled to |p|
    return blocked(o, l, dist) ? 0.05f : 0.05f + cosL;
}

/// One pixel: closest hit, then a shadow ray to the light; Lambert with the geometric normal.
float shadePixel(RTCScene es, const Ray& r, const Vec3& light) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = r.o.x, rh.ray.org_y = r.o.y, rh.ray.org_z = r.o.z;
    rh.ray.dir_x = r.d.x, rh.ray.dir_y = r.d.y, rh.ray.dir_z = r.d.z;
    rh.ray.tnear = 0.f;
    rh.ray.tfar = INFINITY;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(es, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0.f;
    return lambert(r, rh.ray.tfar, Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), light, [&](const Vec3& o, const Vec3& l, float dist) {
        RTCRay sr{};
        sr.org_x = o.x, sr.org_y = o.y, sr.org_z = o.z;
        sr.dir_x = l.x, sr.dir_y = l.y, sr.dir_z = l.z;
        sr.tnear = 0.f;
        sr.tfar = dist;
        sr.mask = ~0u;
        rtcOccluded1(es, &ctx, &sr);
        return sr.tfar < 0.f;
    });
}

/// The triangles in the order of Scene's primitive ids (mesh by mesh), as buildEmbreeScene
/// numbers them: the geometric normal of a rayfarm hit, computed as Embree computes Ng.
std::vector<Vec3> flatTriangles(const Scene& scene) {
    std::vector<Vec3> v;
    for (const TriangleMesh& m : scene.geometry.meshes)
        for (uint32_t i : m.indices) v.push_back(m.positions[i]);
    return v;
}

/// shadePixel with rayfarm's traversal (the scene holds triangles only: main checks).
float shadePixelRayfarm(const Scene& scene, const std::vector<Vec3>& tris, const Ray& r, const Vec3& light) {
    Hit h;
    if (!scene.geometry.intersect(r, h)) return 0.f;
    const Vec3* v = &tris[3 * size_t(h.prim)];
    return lambert(r, h.t, glm::cross(v[1] - v[0], v[2] - v[0]), light, [&](const Vec3& o, const Vec3& l, float dist) {
        Ray sr;
        sr.o = o;
        sr.d = l;
        return scene.geometry.occluded(sr, dist);
    });
}

}  // namespace

int main(int argc, char** argv) {
    std::string path, out, tracer = "embree";
    int threads = 1;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
        else if (a == "--out" && i + 1 < argc) out = argv[++i];
        else if (a == "--tracer" && i + 1 < argc) tracer = argv[++i];
        else path = a;
    }
    if (path.empty() || (tracer != "embree" && tracer != "rayfarm")) {
        std::fprintf(stderr, "usage: embree_bench SCENE.json [--threads N] [--tracer embree|rayfarm] [--out frame0.png]\n");
        return 2;
    }
    const bool own = tracer == "rayfarm";
    try {
        const auto t0 = std::chrono::steady_clock::now();
        DiskFileSource fs;
        LoadedScene loaded = loadScene(path, fs);
        Scene& scene = loaded.scene;
        const anim::Timeline timeline = anim::Timeline::fromScene(loaded);
        if (timeline.animatesGeometry()) throw std::runtime_error("the orbit must not move geometry");
        // Embree gets the triangle meshes alone: spheres and planes would be left out of its
        // picture but not of rayfarm's.
        if (!scene.geometry.spheres.empty() || !scene.geometry.planes.empty())
            throw std::runtime_error(path + ": triangle meshes only, no spheres or planes");
        Vec3 light(0.f);
        bool haveLight = false;
        for (const Light& l : scene.lights)
            if (l.type == LightType::Point && !haveLight) light = l.position, haveLight = true;
        if (!haveLight) throw std::runtime_error(path + ": needs a point light");
        const std::string config = "threads=" + std::to_string(threads);
        RTCDevice device = own ? nullptr : rtcNewDevice(config.c_str());
        RTCScene es = own ? nullptr : buildEmbreeScene(device, scene);
        const std::vector<Vec3> tris = own ? flatTriangles(scene) : std::vector<Vec3>();
        const auto t1 = std::chrono::steady_clock::now();
        const int w = scene.settings.width, h = scene.settings.height, frames = timeline.frameCount();
        std::vector<float> img(size_t(w) * h);
        timeline.applyFrame(scene, 0);
        const float camDist = glm::length(scene.camera.eye - scene.camera.target);
        double checksum = 0.0;
        long long hits = 0;
        const double cpu0 = rf::bench::processCpuSeconds();
        for (int f = 0; f < frames; ++f) {
            timeline.applyFrame(scene, f);
            const CameraRays cam(scene.camera, w, h);
            // Rows of 16×16 tiles handed out dynamically, as rayfarm's frame loop does.
            const int tilesX = (w + 15) / 16, tiles = tilesX * ((h + 15) / 16);
            std::atomic<int> next{0};
            auto work = [&] {
                for (int t; (t = next.fetch_add(1)) < tiles;) {
                    const int x0 = 16 * (t % tilesX), y0 = 16 * (t / tilesX);
                    for (int y = y0; y < std::min(h, y0 + 16); ++y)
                        for (int x = x0; x < std::min(w, x0 + 16); ++x)
                            img[size_t(y) * w + x] = own ? shadePixelRayfarm(scene, tris, cam.generate(x + 0.5f, y + 0.5f), light)
                                                         : shadePixel(es, cam.generate(x + 0.5f, y + 0.5f), light);
                }
            };
            std::vector<std::thread> pool;
            for (int i = 1; i < threads; ++i) pool.emplace_back(work);
            work();
            for (std::thread& t : pool) t.join();
            for (float v : img) checksum += v, hits += v > 0.f;
            if (f == 0 && !out.empty()) {
                std::vector<uint8_t> rgb(img.size() * 3);
                for (size_t i = 0; i < img.size(); ++i) rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = toByte(img[i]);
                writePng(out, w, h, rgb);
            }
        }
        const auto t2 = std::chrono::steady_clock::now();
        const double cpu = rf::bench::processCpuSeconds() - cpu0;
        const double loadS = std::chrono::duration<double>(t1 - t0).count();
        const double renderS = std::chrono::duration<double>(t2 - t1).count();
        std::printf(
            "%s: %d frames %dx%d, %d thread%s, %zu triangles: load + build %.3f s, render %.3f s (%.2f fps, "
            "%.1f ms CPU per frame), %.1f%% of pixels hit, camera %.4g from its target, checksum %.1f\n",
            own ? "rayfarm-bvh" : "embree", frames, w, h, threads, threads > 1 ? "s" : "",
            scene.geometry.triangleCount(), loadS, renderS, frames / renderS, 1e3 * cpu / frames,
            100.0 * hits / (double(w) * h * frames), camDist, checksum);
        if (es) rtcReleaseScene(es);
        if (device) rtcReleaseDevice(device);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "embree_bench: error: %s\n", e.what());
        return 2;
    }
    return 0;
}
