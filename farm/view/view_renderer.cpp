#include "view_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "image.h"
#include "render.h"

namespace rf::view {

std::vector<int> refinementSpp(int targetSpp) {
    const int n = std::max(1, static_cast<int>(std::lround(std::sqrt(double(std::max(1, targetSpp))))));
    std::vector<int> out;
    for (int k = 1; k < n; k *= 2) out.push_back(k * k);
    out.push_back(n * n);
    return out;
}

int nextMovingScale(int scale, double ms) {
    // Input that arrives while a moving frame renders waits for it and then for its own frame:
    // latency is about two frame times, so 20 ms frames keep it near the 50 ms target.
    if (ms > kMovingFrameMs && scale < 4) return scale * 2;
    if (ms * 4.0 < 0.75 * kMovingFrameMs && scale > 1) return scale / 2;
    return scale;
}

ViewRenderer::ViewRenderer(Scene scene, anim::Timeline timeline, RenderSettings settings, int threads, Publish publish)
    : pristine_(scene), scene_(std::move(scene)), timeline_(std::move(timeline)), settings_(settings),
      threads_(threads > 0 ? threads : hardwareThreads()), publish_(std::move(publish)) {
    thread_ = std::thread([this] { loop(); });
}

ViewRenderer::~ViewRenderer() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        ++epoch_;  // cancels the pass in flight at its next tile
    }
    cv_.notify_all();
    thread_.join();
}

uint64_t ViewRenderer::request(const ViewRequest& r) {
    uint64_t e;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        pending_ = r;
        e = ++epoch_;
    }
    cv_.notify_all();
    return e;
}

void ViewRenderer::setTimeline(const anim::Timeline& tl, const std::string&) {
    std::lock_guard<std::mutex> lock(mutex_);
    pendingTimeline_ = tl;
}

std::string ViewRenderer::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

void ViewRenderer::loop() {
    for (;;) {
        ViewRequest r;
        uint64_t epoch;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            cv_.wait(lock, [&] { return stop_ || pending_; });
            if (stop_) return;
            r = *pending_;
            pending_.reset();
            epoch = epoch_.load();
            if (pendingTimeline_) {
                timeline_ = std::move(*pendingTimeline_);
                pendingTimeline_.reset();
                scene_ = pristine_;
                appliedFrame_ = -1;
            }
        }
        try {
            if (r.frame != appliedFrame_) {
                timeline_.applyFrame(scene_, r.frame);
                appliedFrame_ = r.frame;
            }
            const Camera cam = r.followTimeline ? scene_.camera : r.camera;
            ViewFrame frame;
            if (r.moving) {
                const auto t0 = Clock::now();
                if (!renderPass(r, cam, epoch, 1, scale_, frame)) continue;
                // Hold about 30 fps: halve the resolution when a frame is slow, restore it when
                // the next size up would still be fast.
                const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                if (ms > 30.0 && scale_ < 4) scale_ *= 2;
                else if (ms * 4.0 < 20.0 && scale_ > 1) scale_ /= 2;
                continue;
            }
            for (int spp : refinementSpp(settings_.spp))
                if (!renderPass(r, cam, epoch, spp, 1, frame)) break;
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = e.what();
            return;
        }
    }
}

bool ViewRenderer::renderPass(const ViewRequest& r, const Camera& cam, uint64_t epoch, int spp, int scale,
                              ViewFrame& frame) {
    RenderSettings s = settings_;
    s.spp = spp;
    s.width = std::max(1, (settings_.width + scale - 1) / scale);
    s.height = std::max(1, (settings_.height + scale - 1) / scale);
    const auto t0 = Clock::now();
    // A refinement pass paints over the previous pass of the same size, so partial pictures
    // show the new tiles on top of the old ones rather than on black.
    if (frame.width != s.width || frame.height != s.height) frame.rgb.assign(size_t(s.width) * s.height * 3, 0);
    frame.epoch = epoch;
    frame.width = s.width;
    frame.height = s.height;
    frame.spp = spp;
    frame.moving = r.moving;
    frame.camera = cam;
    frame.frame = r.frame;
    frame.input = r.input;
    const int tilesX = (settings_.width + kTile - 1) / kTile, tilesY = (settings_.height + kTile - 1) / kTile;
    frame.tileRank.assign(size_t(tilesX) * tilesY, 0);  // one process: every tile is rank 0's
    const std::vector<TileRect> tiles = makeTiles(s.width, s.height, kTile);
    std::mutex frameMutex;
    auto lastPublish = t0;
    auto publishCopy = [&](bool complete) {
        ViewFrame copy = frame;
        copy.complete = complete;
        copy.final = complete && (r.moving || spp == settings_.spp);
        copy.passMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        publish_(std::move(copy));
    };
    parallelFor(static_cast<int>(tiles.size()), threads_, [&](int i, int thread) {
        if (cancelled(epoch)) return;
        const TileRect& t = tiles[size_t(i)];
        Image tile(t.width(), t.height());
        RayStats rays;
        renderTile(scene_, cam, t, s, r.frame, tile.data(), rays);
        if (cancelled(epoch)) return;
        const std::vector<uint8_t> bytes = toRgb8(tile, s);
        std::lock_guard<std::mutex> lock(frameMutex);
        for (int y = 0; y < t.height(); ++y)
            std::memcpy(&frame.rgb[(size_t(t.y0 + y) * s.width + t.x0) * 3], &bytes[size_t(y) * t.width() * 3],
                        size_t(t.width()) * 3);
        // Slow passes show their progress a few times a second.
        if (thread == 0 && Clock::now() - lastPublish > std::chrono::milliseconds(150)) {
            lastPublish = Clock::now();
            publishCopy(false);
        }
    });
    if (cancelled(epoch)) return false;
    publishCopy(true);
    return true;
}

}  // namespace rf::view
