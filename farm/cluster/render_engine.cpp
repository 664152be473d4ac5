#include "render_engine.h"

#include <chrono>
#include <cstdlib>
#include <cstring>

#include "image.h"
#include "render.h"

namespace rf::farm {

namespace {

/// The linear plane of a PixelLayout: premultiplied RGBA floats, interleaved (alpha 1 where the
/// background is not transparent). Copied byte-wise: the plane need not be float-aligned.
void appendLinearPlane(const std::vector<float>& rgb, const std::vector<float>& alpha, bool transparent, uint8_t* dst) {
    const size_t pixels = alpha.size();
    for (size_t i = 0; i < pixels; ++i) {
        const float px[4] = {rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2], transparent ? alpha[i] : 1.f};
        std::memcpy(dst + i * sizeof px, px, sizeof px);
    }
}

}  // namespace

RenderEngine::RenderEngine(Scene scene, anim::Timeline timeline, RenderSettings settings, int threads, bool linear,
                           ItemRenderer itemRenderer)
    : scene_(std::move(scene)), timeline_(std::move(timeline)), settings_(settings), threads_(std::max(1, threads)), linear_(linear),
      itemRenderer_(std::move(itemRenderer)) {
    thread_ = std::thread([this] { loop(); });
}

RenderEngine::~RenderEngine() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        queue_.clear();
        cancelCurrent_ = true;  // its result would go nowhere
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

void RenderEngine::setView(const ViewSpec& v) {
    std::lock_guard<std::mutex> lock(mutex_);
    view_ = v;
    const size_t before = queue_.size();
    std::erase_if(queue_, [&](const WorkItem& i) { return i.epoch != v.epoch; });
    outstanding_ -= int(before - queue_.size());
    if (current_ >= 0 && currentEpoch_ != v.epoch) cancelCurrent_ = true;
}

void RenderEngine::setScene(Scene scene, anim::Timeline timeline) {
    std::lock_guard<std::mutex> lock(mutex_);
    nextScene_.emplace(std::move(scene), std::move(timeline));
}

bool RenderEngine::next(WorkItem& item, std::optional<ViewSpec>& view) {
    std::unique_lock<std::mutex> lock(mutex_);
    workCv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return false;
    item = queue_.front();
    queue_.pop_front();
    current_ = item.frame;
    currentEpoch_ = item.epoch;
    cancelCurrent_ = false;
    view.reset();
    if (item.epoch != 0 && view_ && view_->epoch == item.epoch) view = view_;
    if (nextScene_) {
        scene_ = std::move(nextScene_->first);
        timeline_ = std::move(nextScene_->second);
        nextScene_.reset();
        appliedFrame_ = -1;
    }
    return true;
}

void RenderEngine::loop() {
    WorkItem item;
    std::optional<ViewSpec> view;
    while (next(item, view)) {
        try {
            TileResult r = itemRenderer_ && !view ? itemRenderer_(item, scene_.transparentBackground ? 4 : 3)
                                                  : render(scene_, timeline_, settings_, threads_, item, appliedFrame_, linear_,
                                                           view ? &*view : nullptr, &cancelCurrent_);
            std::lock_guard<std::mutex> lock(mutex_);
            current_ = -1;
            if (cancelCurrent_) {
                --outstanding_;  // a newer view replaced it: no result
                continue;
            }
            results_.push_back(std::move(r));
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

TileResult RenderEngine::render(Scene& scene, const anim::Timeline& tl, const RenderSettings& job, int threads,
                                const WorkItem& item, int& appliedFrame, bool linear, const ViewSpec* view,
                                const std::atomic<bool>* cancel) {
    RenderSettings s = job;
    if (view) s.spp = view->spp, s.width = view->width, s.height = view->height;
    const auto t0 = std::chrono::steady_clock::now();
    if (appliedFrame != item.frame) {
        // The timeline overwrites absolute state, so frames may come in any order.
        tl.applyFrame(scene, item.frame);
        appliedFrame = item.frame;
    }
    const TileRect& rect = item.rect;
    // Small rectangles (pixel mode) are split finer so every thread gets several pieces.
    const int sub = rect.pixels() <= 128 * 128 ? 16 : std::max(8, s.tileSize);
    TileResult out;
    out.item = item;
    out.layout.channels = scene.transparentBackground ? 4 : 3;
    out.layout.linear = linear;
    const size_t pixels = size_t(rect.pixels());
    out.rgb.resize(out.layout.bytes(pixels));
    RectBuffers buffers;
    (out.layout.channels == 4 ? buffers.rgba8 : buffers.rgb8) = out.rgb.data();
    std::vector<float> rgbLinear(linear ? 3 * pixels : 0), alpha(linear ? pixels : 0);
    if (linear) buffers.linear = rgbLinear.data(), buffers.alpha = alpha.data();
    const Camera& camera = view && !view->followTimeline ? view->camera : scene.camera;
    renderRect(scene, camera, s, item.frame, rect, threads, sub, buffers, out.rays, cancel);
    if (linear) appendLinearPlane(rgbLinear, alpha, scene.transparentBackground, out.rgb.data() + out.layout.linearOffset(pixels));
    out.busySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace rf::farm
