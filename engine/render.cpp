#include "render.h"

#include <atomic>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>

#include "sampler.h"
#include "integrator.h"

namespace rf {

void renderTile(const Scene& scene, const Camera& camera, const TileRect& rect, const RenderSettings& settings,
                int frame, float* out, RayStats& stats, float* alpha) {
    const CameraRays rays(camera, settings.width, settings.height);
    const std::unique_ptr<Integrator> integrator = makeIntegrator(scene, settings);
    const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(std::max(1, settings.spp))))));
    const float invN = 1.f / n;
    const float invSpp = 1.f / (n * n);
    const bool seeded = integrator->usesSeed();
    // Counted on this thread's stack and added once: callers keep one RayStats per thread side
    // by side, and bumping those per ray would bounce a shared cache line between cores.
    RayStats local;
    for (int y = rect.y0; y < rect.y1; ++y) {
        for (int x = rect.x0; x < rect.x1; ++x) {
            const uint64_t pixel = uint64_t(y) * uint64_t(settings.width) + uint64_t(x);
            Color sum(0.f);
            float hits = 0.f;  // coverage: whole samples add exactly, as the count of hits did
            for (int sy = 0; sy < n; ++sy) {
                for (int sx = 0; sx < n; ++sx) {
                    float jx = 0.5f, jy = 0.5f;
                    if (n > 1) {  // one sample sits at the pixel centre; more are jittered per stratum
                        SampleRng rng(frame, pixel, uint64_t(sy * n + sx));
                        jx = rng.next();
                        jy = rng.next();
                    }
                    Ray r = rays.generate(x + (sx + jx) * invN, y + (sy + jy) * invN);
                    r.coneSpread *= invN;  // each of n×n samples covers its stratum of the pixel
                    float covered = 0.f;
                    const uint64_t seed = seeded ? sampleSeed(frame, pixel, uint64_t(sy * n + sx)) : kNoSampleSeed;
                    Color c = integrator->Li(r, seed, local, alpha ? &covered : nullptr);
                    hits += covered;
                    if (!isFinite(c)) {
                        c = Color(0.f);
                        ++local.nonFinite;
                    }
                    sum += c;
                }
            }
            sum *= invSpp;
            float* o = out + 3 * (size_t(y - rect.y0) * rect.width() + (x - rect.x0));
            o[0] = sum.r;
            o[1] = sum.g;
            o[2] = sum.b;
            if (alpha) alpha[size_t(y - rect.y0) * rect.width() + (x - rect.x0)] = hits * invSpp;
        }
    }
    stats += local;
}

std::vector<TileRect> makeTiles(int width, int height, int tileSize) {
    std::vector<TileRect> tiles;
    tileSize = std::max(1, tileSize);
    for (int y = 0; y < height; y += tileSize)
        for (int x = 0; x < width; x += tileSize)
            tiles.push_back({x, y, std::min(width, x + tileSize), std::min(height, y + tileSize)});
    return tiles;
}

int hardwareThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

void parallelFor(int n, int threads, const std::function<void(int, int)>& job) {
    if (threads <= 0) threads = hardwareThreads();
    threads = std::max(1, std::min(threads, n));
    std::atomic<int> next{0};
    std::exception_ptr error;
    std::mutex errorMutex;
    auto worker = [&](int t) {
        for (;;) {
            const int i = next.fetch_add(1);
            if (i >= n) return;
            try {
                job(i, t);
            } catch (...) {
                std::lock_guard<std::mutex> lock(errorMutex);
                if (!error) error = std::current_exception();
                next = n;
                return;
            }
        }
    };
    if (threads == 1) {
        worker(0);
    } else {
        std::vector<std::thread> pool;
        for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
        worker(0);
        for (auto& th : pool) th.join();
    }
    if (error) std::rethrow_exception(error);
}

void renderRect(const Scene& scene, const Camera& camera, const RenderSettings& settings, int frame, const TileRect& rect,
                int threads, int subTile, const RectBuffers& out, RayStats& stats, const std::atomic<bool>* cancel) {
    std::vector<TileRect> subs = makeTiles(rect.width(), rect.height(), subTile);
    for (TileRect& t : subs) t = {t.x0 + rect.x0, t.y0 + rect.y0, t.x1 + rect.x0, t.y1 + rect.y0};
    if (threads <= 0) threads = hardwareThreads();
    std::vector<RayStats> perThread(size_t(std::max(1, threads)));
    const size_t stride = size_t(rect.width());
    parallelFor(static_cast<int>(subs.size()), threads, [&](int i, int thread) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return;
        const TileRect& t = subs[size_t(i)];
        const bool wantAlpha = out.alpha || out.rgba8;
        std::vector<float> rgb(size_t(t.pixels()) * 3), alpha(wantAlpha ? size_t(t.pixels()) : 0);
        renderTile(scene, camera, t, settings, frame, rgb.data(), perThread[size_t(thread)], wantAlpha ? alpha.data() : nullptr);
        const size_t w = size_t(t.width());
        for (int y = 0; y < t.height(); ++y) {
            const size_t at = size_t(t.y0 - rect.y0 + y) * stride + size_t(t.x0 - rect.x0);
            const float* src = rgb.data() + 3 * size_t(y) * w;
            if (out.linear) std::memcpy(out.linear + 3 * at, src, sizeof(float) * 3 * w);
            if (out.alpha) std::memcpy(out.alpha + at, alpha.data() + size_t(y) * w, sizeof(float) * w);
            // Encoded here, on the rendering thread: sRGB's pow per channel is a sizeable share
            // of a cheap frame, and would otherwise run on one core after the render.
            const float scale = exposureScale(settings.exposure);
            if (out.rgb8) encodeRgb8(src, 3 * w, settings.toneMap, out.rgb8 + 3 * at, scale);
            for (size_t x = 0; out.rgba8 && x < w; ++x)
                toRgba8Pixel(src + 3 * x, alpha[size_t(y) * w + x], settings.toneMap, out.rgba8 + 4 * (at + x), scale);
        }
    });
    for (const RayStats& r : perThread) stats += r;
}

Image renderFrame(const Scene& scene, const Camera& camera, const RenderSettings& settings, int frame, int threads,
                  RayStats& stats) {
    Image img(settings.width, settings.height, scene.transparentBackground);
    const TileRect whole{0, 0, settings.width, settings.height};
    renderRect(scene, camera, settings, frame, whole, threads, settings.tileSize,
               {img.data(), img.hasAlpha() ? img.alphaData() : nullptr, nullptr}, stats);
    return img;
}

}  // namespace rf
