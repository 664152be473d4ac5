#include "engine/integrators/render.h"

#include <atomic>
#include <cstring>

#include "engine/integrators/bounce_cache.h"
#include "engine/integrators/integrator.h"
#include "engine/util/sampler.h"

namespace rf {

namespace {
/// Camera rays go to the integrator in packets of the pixels of one kPacketSide² block of the
/// image (aligned to multiples of kPacketSide, cut only by the image's edge), one sample of
/// each pixel at a time. A block is the same packet whichever rectangle asks for some of its
/// pixels, so a pixel's result never depends on the tiling.
constexpr int kPacketSide = 4;
static_assert(kPacketSide * kPacketSide <= 64, "a packet's wanted pixels are a 64-bit mask");
}  // namespace

void renderTile(const Scene& scene, const RenderView& view, const TileRect& rect, int frame, float* out,
                RayStats& stats, float* alpha) {
    const RenderSettings& settings = view.settings;
    const CameraRays rays(view.camera, settings.width, settings.height);
    const std::unique_ptr<Integrator> integrator = makeIntegrator(scene, settings, view.bounceSlot.get());
    const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(std::max(1, settings.spp))))));
    const float invN = 1.f / n;
    const float invSpp = 1.f / (n * n);
    const bool seeded = integrator->usesSeed();
    // Counted on this thread's stack and added once: callers keep one RayStats per thread side
    // by side, and bumping those per ray would bounce a shared cache line between cores.
    RayStats local;
    constexpr int kMax = kPacketSide * kPacketSide;
    Ray packet[kMax];
    uint64_t seeds[kMax];
    Color radiance[kMax], sum[kMax];
    float covered[kMax], hits[kMax];
    int px[kMax], py[kMax];
    const int bx0 = rect.x0 - rect.x0 % kPacketSide, by0 = rect.y0 - rect.y0 % kPacketSide;
    for (int by = by0; by < rect.y1; by += kPacketSide) {
        for (int bx = bx0; bx < rect.x1; bx += kPacketSide) {
            // The block's pixels in the image, row by row; the rectangle wants some of them.
            int count = 0;
            uint64_t wanted = 0;
            for (int y = by; y < std::min(by + kPacketSide, settings.height); ++y)
                for (int x = bx; x < std::min(bx + kPacketSide, settings.width); ++x) {
                    if (x >= rect.x0 && x < rect.x1 && y >= rect.y0 && y < rect.y1) wanted |= uint64_t(1) << count;
                    px[count] = x;
                    py[count] = y;
                    sum[count] = Color(0.f);
                    hits[count] = 0.f;  // coverage: whole samples add exactly, as the count of hits did
                    ++count;
                }
            for (int sy = 0; sy < n; ++sy) {
                for (int sx = 0; sx < n; ++sx) {
                    const uint64_t sample = uint64_t(sy * n + sx);
                    for (int i = 0; i < count; ++i) {
                        const uint64_t pixel = uint64_t(py[i]) * uint64_t(settings.width) + uint64_t(px[i]);
                        float jx = 0.5f, jy = 0.5f;
                        if (n > 1) {  // one sample sits at the pixel centre; more are jittered per stratum
                            SampleRng rng(frame, pixel, sample);
                            jx = rng.next();
                            jy = rng.next();
                        }
                        packet[i] = rays.generate(px[i] + (sx + jx) * invN, py[i] + (sy + jy) * invN);
                        packet[i].coneSpread *= invN;  // each of n×n samples covers its stratum of the pixel
                        packet[i].coneWidth *= invN;
                        seeds[i] = seeded ? sampleSeed(frame, pixel, sample) : kNoSampleSeed;
                        covered[i] = 0.f;
                    }
                    if (settings.packets)
                        integrator->LiPacket(packet, count, wanted, seeds, local, radiance, alpha ? covered : nullptr);
                    else  // ray by ray, as the Integrator interface defines a packet
                        integrator->Integrator::LiPacket(packet, count, wanted, seeds, local, radiance,
                                                         alpha ? covered : nullptr);
                    for (uint64_t m = wanted; m; m &= m - 1) {
                        const int i = __builtin_ctzll(m);
                        hits[i] += covered[i];
                        Color c = radiance[i];
                        if (!isFinite(c)) {
                            c = Color(0.f);
                            ++local.nonFinite;
                        }
                        sum[i] += c;
                    }
                }
            }
            for (uint64_t m = wanted; m; m &= m - 1) {
                const int i = __builtin_ctzll(m);
                const size_t at = size_t(py[i] - rect.y0) * rect.width() + size_t(px[i] - rect.x0);
                const Color c = sum[i] * invSpp;
                out[3 * at] = c.r;
                out[3 * at + 1] = c.g;
                out[3 * at + 2] = c.b;
                if (alpha) alpha[at] = hits[i] * invSpp;
            }
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

void renderRect(const Scene& scene, const RenderView& view, int frame, const TileRect& rect, int threads, int subTile,
                const RectBuffers& out, RayStats& stats, const std::atomic<bool>* cancel) {
    renderRects(scene, view, frame, {RectJob{rect, out, &stats}}, threads, subTile, cancel);
}

void renderRects(const Scene& scene, const RenderView& given, int frame, const std::vector<RectJob>& jobs, int threads,
                 int subTile, const std::atomic<bool>* cancel) {
    // A view whose slot was reset to null: one slot for this call, so that its tiles share one
    // cache instead of each building its own.
    RenderView local;
    if (!given.bounceSlot) local = {given.camera, given.settings, std::make_shared<SceneCacheSlot>()};
    const RenderView& view = given.bounceSlot ? given : local;
    const RenderSettings& settings = view.settings;
    struct Sub {
        TileRect t;
        size_t job;
    };
    std::vector<Sub> subs;
    for (size_t j = 0; j < jobs.size(); ++j) {
        const TileRect& rect = jobs[j].rect;
        for (const TileRect& t : makeTiles(rect.width(), rect.height(), subTile))
            subs.push_back({{t.x0 + rect.x0, t.y0 + rect.y0, t.x1 + rect.x0, t.y1 + rect.y0}, j});
    }
    if (threads <= 0) threads = hardwareThreads();
    // The bounce cache, built here on every thread if the geometry or lights moved since the
    // last rectangle; each tile's integrator then finds it ready (its counts go to the first's).
    RayStats cacheStats;
    const std::shared_ptr<const BounceCache> bounce =
        bounceCache(scene, settings, view.bounceSlot.get(), threads, &cacheStats);
    // Per job and thread, added at the end: threads bumping one shared count would bounce its
    // cache line between cores.
    const size_t nt = size_t(std::max(1, threads));
    std::vector<RayStats> perThread(jobs.size() * nt);
    const float scale = exposureScale(settings.exposure);
    parallelFor(static_cast<int>(subs.size()), threads, [&](int i, int thread) {
        if (cancel && cancel->load(std::memory_order_relaxed)) return;
        const TileRect& t = subs[size_t(i)].t;
        const RectJob& job = jobs[subs[size_t(i)].job];
        const RectBuffers& out = job.out;
        const TileRect& rect = job.rect;
        const size_t stride = size_t(rect.width());
        // An exact background needs the coverage to lay the model over it.
        const bool wantAlpha = out.alpha || out.rgba8 || scene.exactBackground;
        std::vector<float> rgb(size_t(t.pixels()) * 3), alpha(wantAlpha ? size_t(t.pixels()) : 0);
        renderTile(scene, view, t, frame, rgb.data(), perThread[subs[size_t(i)].job * nt + size_t(thread)],
                   wantAlpha ? alpha.data() : nullptr);
        const size_t w = size_t(t.width());
        for (int y = 0; y < t.height(); ++y) {
            const size_t at = size_t(t.y0 - rect.y0 + y) * stride + size_t(t.x0 - rect.x0);
            const float* src = rgb.data() + 3 * size_t(y) * w;
            if (out.linear) std::memcpy(out.linear + 3 * at, src, sizeof(float) * 3 * w);
            if (out.alpha) std::memcpy(out.alpha + at, alpha.data() + size_t(y) * w, sizeof(float) * w);
            // Encoded here, on the rendering thread: sRGB's pow per channel is a sizeable share
            // of a cheap frame, and would otherwise run on one core after the render.
            if (out.rgb8 && scene.exactBackground)
                for (size_t x = 0; x < w; ++x)
                    toRgb8OverPixel(src + 3 * x, alpha[size_t(y) * w + x], settings.toneMap, scene.background,
                                    out.rgb8 + 3 * (at + x), scale);
            else if (out.rgb8)
                encodeRgb8(src, 3 * w, settings.toneMap, out.rgb8 + 3 * at, scale);
            for (size_t x = 0; out.rgba8 && x < w; ++x)
                toRgba8Pixel(src + 3 * x, alpha[size_t(y) * w + x], settings.toneMap, out.rgba8 + 4 * (at + x), scale);
        }
    });
    for (size_t j = 0; j < jobs.size(); ++j) {
        if (!jobs[j].stats) continue;
        if (j == 0) *jobs[j].stats += cacheStats;
        for (size_t k = 0; k < nt; ++k) *jobs[j].stats += perThread[j * nt + k];
    }
}

Image renderFrame(const Scene& scene, const RenderView& view, int frame, int threads, RayStats& stats) {
    const RenderSettings& settings = view.settings;
    Image img(settings.width, settings.height, scene.primaryMissesEmpty());
    if (scene.exactBackground) img.setBackdrop(scene.background);
    const TileRect whole{0, 0, settings.width, settings.height};
    renderRect(scene, view, frame, whole, threads, settings.tileSize,
               {img.data(), img.hasAlpha() ? img.alphaData() : nullptr, nullptr}, stats);
    return img;
}

}  // namespace rf
