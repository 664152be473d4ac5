#pragma once
/// The one entry point for splitting work: render a rectangle of one frame. Local threads, the
/// farm's pixel mode and its frame mode are all schedulers over renderTile.
#include <cstdint>
#include <atomic>
#include <functional>
#include <vector>

#include "engine/util/image.h"
#include "engine/util/parallel.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"
#include "engine/util/stats.h"

namespace rf {

/// Half-open pixel rectangle [x0, x1) × [y0, y1).
struct TileRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    int pixels() const { return width() * height(); }
};

/// What a frame is seen through: the one source of the camera and settings the render loop
/// reads. Scene::camera and Scene::settings are what the scene file (and the timeline's pose)
/// say; the render calls below never read them, only the view they are handed, which callers
/// make from them, from the job's settings or from an interactive view.
struct RenderView {
    Camera camera;
    RenderSettings settings;
    /// Where the bounce cache (bounce_cache.h) is kept between frames: the job's, so that all
    /// its frames (and the head start and metering before them) share one. A view made without
    /// one gets a slot of its own, and builds the cache for itself.
    std::shared_ptr<SceneCacheSlot> bounceSlot = std::make_shared<SceneCacheSlot>();
};

/// Renders rect of frame `frame` into out (rect.pixels() × 3 linear floats, row-major). The
/// result depends only on (scene, view, frame, pixel): never on thread or rank.
/// Non-finite sample values are replaced by black and counted in stats.nonFinite.
/// alpha (if given, rect.pixels() floats): coverage, the fraction of the pixel's samples whose
/// primary ray met geometry. With scene.transparentBackground or scene.exactBackground the colour
/// is premultiplied by it (misses add nothing).
void renderTile(const Scene& scene, const RenderView& view, const TileRect& rect, int frame, float* out,
                RayStats& stats, float* alpha = nullptr);

/// Splits a width × height image into tiles of tileSize, row by row.
std::vector<TileRect> makeTiles(int width, int height, int tileSize);

/// Where renderRect puts a rectangle's pixels, each row-major over the rectangle; any may be
/// null.
struct RectBuffers {
    float* linear = nullptr;  ///< 3 floats a pixel: linear radiance (as renderTile: premultiplied)
    float* alpha = nullptr;   ///< 1 float a pixel: coverage (as renderTile)
    /// 3 bytes a pixel: tone-mapped and sRGB-encoded (encodeRgb8); over an exact background,
    /// laid over it (toRgb8OverPixel).
    uint8_t* rgb8 = nullptr;
    /// 4 bytes a pixel: straight RGBA (toRgba8Pixel), for a transparent background's frames.
    uint8_t* rgba8 = nullptr;
};

/// The one frame loop: renders rect of frame `frame` on `threads` threads (0: all cores), which
/// pull sub-tiles of subTile × subTile pixels and write them to out. Local frames, the farm's
/// pixel-mode tiles and frame-mode frames all come through here, so their pixels agree bit for
/// bit (a pixel depends only on its own coordinates, never on how the rectangle was cut).
/// cancel: when it reads true, the sub-tiles not yet begun are skipped (the rectangle is then
/// incomplete and the caller drops it): an interactive view replaced by a newer one.
void renderRect(const Scene& scene, const RenderView& view, int frame, const TileRect& rect, int threads, int subTile,
                const RectBuffers& out, RayStats& stats, const std::atomic<bool>* cancel = nullptr);

/// One rectangle of renderRects: where its pixels go, and its own ray counts.
struct RectJob {
    TileRect rect;
    RectBuffers out;
    RayStats* stats = nullptr;
};

/// renderRect for several rectangles of the same frame at once: the threads pull sub-tiles of
/// all of them, so rectangles smaller than the threads' share of work (a farm rank's small
/// tiles) still keep every thread busy. Each rectangle's pixels are those renderRect gives.
void renderRects(const Scene& scene, const RenderView& view, int frame, const std::vector<RectJob>& jobs, int threads,
                 int subTile, const std::atomic<bool>* cancel = nullptr);

/// Renders a whole frame with `threads` worker threads (0: all cores) pulling tiles. The image
/// has an alpha plane when the scene's background is transparent or exact, and the exact
/// background as its backdrop (Image::setBackdrop).
Image renderFrame(const Scene& scene, const RenderView& view, int frame, int threads, RayStats& stats);

}  // namespace rf
