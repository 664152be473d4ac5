#include "render_engine.h"

#include <chrono>

#include "image.h"
#include "render.h"

namespace rf::farm {

RenderEngine::RenderEngine(Scene scene, anim::Timeline timeline, RenderSettings settings, int threads)
    : scene_(std::move(scene)), timeline_(std::move(timeline)), settings_(settings), threads_(std::max(1, threads)) {
    thread_ = std::thread([this] { loop(); });
}

RenderEngine::~RenderEngine() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        queue_.clear();
    }
    workCv_.notify_all();
    thread_.join();
}

void RenderEngine::submit(const WorkItem& item) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queue_.push_back(item);
        ++outstanding_;
    }
    workCv_.notify_one();
}

std::optional<TileResult> RenderEngine::takeResult(double waitSeconds) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (results_.empty() && waitSeconds > 0.0)
        resultCv_.wait_for(lock, std::chrono::duration<double>(waitSeconds),
                           [&] { return !results_.empty() || !error_.empty(); });
    if (results_.empty()) return std::nullopt;
    TileResult r = std::move(results_.front());
    results_.pop_front();
    --outstanding_;
    return r;
}

int RenderEngine::outstanding() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return outstanding_;
}

int RenderEngine::currentFrame() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return current_;
}

std::string RenderEngine::error() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

void RenderEngine::cancelQueued() {
    std::lock_guard<std::mutex> lock(mutex_);
    outstanding_ -= int(queue_.size());
    queue_.clear();
}

void RenderEngine::loop() {
    for (;;) {
        WorkItem item;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            workCv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            item = queue_.front();
            queue_.pop_front();
            current_ = item.frame;
        }
        try {
            TileResult r = render(scene_, timeline_, settings_, threads_, item, appliedFrame_);
            std::lock_guard<std::mutex> lock(mutex_);
            results_.push_back(std::move(r));
            current_ = -1;
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = "frame " + std::to_string(item.frame) + ": " + e.what();
            current_ = -1;
            resultCv_.notify_all();
            return;
        }
        resultCv_.notify_all();
    }
}

TileResult RenderEngine::render(Scene& scene, const anim::Timeline& tl, const RenderSettings& s, int threads,
                                const WorkItem& item, int& appliedFrame) {
    const auto t0 = std::chrono::steady_clock::now();
    if (appliedFrame != item.frame) {
        // The timeline overwrites absolute state, so frames may come in any order.
        tl.applyFrame(scene, item.frame);
        appliedFrame = item.frame;
    }
    const TileRect& rect = item.rect;
    // Small rectangles (pixel mode) are split finer so every thread gets several pieces.
    const int sub = rect.pixels() <= 128 * 128 ? 16 : std::max(8, s.tileSize);
    std::vector<TileRect> subs = makeTiles(rect.width(), rect.height(), sub);
    for (TileRect& t : subs) t = {t.x0 + rect.x0, t.y0 + rect.y0, t.x1 + rect.x0, t.y1 + rect.y0};

    TileResult out;
    out.item = item;
    out.rgb.resize(size_t(rect.pixels()) * 3);
    std::vector<RayStats> perThread(size_t(std::max(1, threads)));
    parallelFor(int(subs.size()), threads, [&](int i, int thread) {
        const TileRect& t = subs[size_t(i)];
        std::vector<float> buf(size_t(t.pixels()) * 3);
        renderTile(scene, scene.camera, t, s, item.frame, buf.data(), perThread[size_t(thread)]);
        // The same mapping as toRgb8, so tiles assemble into the identical frame.
        const float scale = exposureScale(s.exposure);
        for (int y = 0; y < t.height(); ++y) {
            uint8_t* dst = out.rgb.data() + 3 * (size_t(t.y0 - rect.y0 + y) * rect.width() + size_t(t.x0 - rect.x0));
            toSrgb8(buf.data() + 3 * size_t(y) * t.width(), size_t(t.width()), s.toneMap, scale, dst);
        }
    });
    for (const RayStats& r : perThread) out.rays += r;
    out.busySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace rf::farm
