#include "farm/cluster/render_engine.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "engine/util/image.h"
#include "engine/integrators/render.h"

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
                           ItemRenderer itemRenderer, std::shared_ptr<SceneCacheSlot> bounceSlot)
    : scene_(std::move(scene)),
      timeline_(std::move(timeline)),
      settings_(settings),
      bounceSlot_(bounceSlot ? std::move(bounceSlot) : std::make_shared<SceneCacheSlot>()),
      threads_(std::max(1, threads)),
      linear_(linear),
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

void RenderEngine::submitAll(const std::vector<WorkItem>& items) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queue_.insert(queue_.end(), items.begin(), items.end());
        outstanding_ += int(items.size());
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

namespace {

/// Items no larger than this are split into 16x16 sub-tiles (pixel mode's tiles), and may be
/// rendered together with the next ones of their frame, until the batch has
/// kSubTilesPerThread sub-tiles a render thread.
constexpr int kSmallItemPixels = 128 * 128;

int subTileFor(const TileRect& rect, const RenderSettings& s) { return rect.pixels() <= kSmallItemPixels ? 16 : std::max(8, s.tileSize); }

int subTilesIn(const TileRect& rect, int sub) { return ((rect.width() + sub - 1) / sub) * ((rect.height() + sub - 1) / sub); }

}  // namespace

bool RenderEngine::next(std::vector<WorkItem>& items, std::optional<ViewSpec>& view) {
    std::unique_lock<std::mutex> lock(mutex_);
    workCv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return false;
    items.assign(1, queue_.front());
    queue_.pop_front();
    const WorkItem first = items[0];  // a copy: items grows below
    // Small items of the same frame and epoch go along, up to a few sub-tiles a thread (a
    // benchmark's stand-in renderer takes them one by one anyway).
    if (!itemRenderer_ && first.rect.pixels() <= kSmallItemPixels) {
        int subTiles = subTilesIn(first.rect, 16);
        while (!queue_.empty() && subTiles < kSubTilesPerThread * threads_) {
            const WorkItem& i = queue_.front();
            if (i.frame != first.frame || i.epoch != first.epoch || i.rect.pixels() > kSmallItemPixels) break;
            subTiles += subTilesIn(i.rect, 16);
            items.push_back(i);
            queue_.pop_front();
        }
    }
    largestBatch_ = std::max(largestBatch_, int(items.size()));
    current_ = first.frame;
    currentEpoch_ = first.epoch;
    cancelCurrent_ = false;
    view.reset();
    if (first.epoch != 0 && view_ && view_->epoch == first.epoch) view = view_;
    if (nextScene_) {
        scene_ = std::move(nextScene_->first);
        timeline_ = std::move(nextScene_->second);
        nextScene_.reset();
        appliedFrame_ = -1;
    }
    return true;
}

int RenderEngine::subTilesOf(const TileRect& rect, const RenderSettings& s) { return subTilesIn(rect, subTileFor(rect, s)); }

int RenderEngine::largestBatch() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return largestBatch_;
}

void RenderEngine::loop() {
    std::vector<WorkItem> items;
    std::optional<ViewSpec> view;
    while (next(items, view)) {
        try {
            std::vector<TileResult> done;
            if (itemRenderer_ && !view) {
                for (const WorkItem& item : items) done.push_back(itemRenderer_(item, scene_.transparentBackground ? 4 : 3));
            } else if (items.size() == 1) {
                done.push_back(render(scene_, timeline_, settings_, threads_, items[0], appliedFrame_, linear_, view ? &*view : nullptr,
                                      &cancelCurrent_, bounceSlot_));
            } else {
                done = renderTogether(scene_, timeline_, settings_, threads_, items, appliedFrame_, linear_, view ? &*view : nullptr,
                                      &cancelCurrent_, bounceSlot_);
            }
            std::lock_guard<std::mutex> lock(mutex_);
            current_ = -1;
            if (cancelCurrent_) {
                outstanding_ -= int(items.size());  // a newer view replaced them: no result
                continue;
            }
            for (TileResult& r : done) results_.push_back(std::move(r));
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mutex_);
            error_ = "frame " + std::to_string(items[0].frame) + ": " + e.what();
            current_ = -1;
            resultCv_.notify_all();
            return;
        }
        resultCv_.notify_all();
    }
}

TileResult RenderEngine::render(Scene& scene, const anim::Timeline& tl, const RenderSettings& job, int threads,
                                const WorkItem& item, int& appliedFrame, bool linear, const ViewSpec* view,
                                const std::atomic<bool>* cancel, const std::shared_ptr<SceneCacheSlot>& bounceSlot) {
    return std::move(
        renderTogether(scene, tl, job, threads, {item}, appliedFrame, linear, view, cancel, bounceSlot)[0]);
}

std::vector<TileResult> RenderEngine::renderTogether(Scene& scene, const anim::Timeline& tl, const RenderSettings& job,
                                                     int threads, const std::vector<WorkItem>& items, int& appliedFrame,
                                                     bool linear, const ViewSpec* view, const std::atomic<bool>* cancel,
                                                     const std::shared_ptr<SceneCacheSlot>& bounceSlot) {
    RenderSettings s = job;
    if (view) s.spp = view->spp, s.width = view->width, s.height = view->height;
    const auto t0 = std::chrono::steady_clock::now();
    const int frame = items.at(0).frame;
    if (appliedFrame != frame) {
        // The timeline overwrites absolute state, so frames may come in any order.
        tl.applyFrame(scene, frame);
        appliedFrame = frame;
    }
    std::vector<TileResult> out(items.size());
    std::vector<std::vector<float>> rgbLinear(items.size()), alpha(items.size());
    std::vector<RectJob> jobs(items.size());
    int64_t totalPixels = 0;
    for (size_t i = 0; i < items.size(); ++i) {
        if (items[i].frame != frame) throw std::logic_error("renderTogether: items of several frames");
        TileResult& r = out[i];
        r.item = items[i];
        r.layout.channels = scene.transparentBackground ? 4 : 3;
        r.layout.linear = linear;
        const size_t pixels = size_t(items[i].rect.pixels());
        totalPixels += int64_t(pixels);
        r.rgb.resize(r.layout.bytes(pixels));
        RectJob& j = jobs[i];
        j.rect = items[i].rect;
        j.stats = &r.rays;
        (r.layout.channels == 4 ? j.out.rgba8 : j.out.rgb8) = r.rgb.data();
        if (linear) {
            rgbLinear[i].resize(3 * pixels);
            alpha[i].resize(pixels);
            j.out.linear = rgbLinear[i].data();
            j.out.alpha = alpha[i].data();
        }
    }
    // Small rectangles (pixel mode) are split finer so every thread gets several pieces.
    const int sub = subTileFor(items[0].rect, s);
    RenderView rv{view && !view->followTimeline ? view->camera : scene.camera, s};
    if (bounceSlot) rv.bounceSlot = bounceSlot;
    renderRects(scene, rv, frame, jobs, threads, sub, cancel);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (size_t i = 0; i < items.size(); ++i) {
        TileResult& r = out[i];
        const size_t pixels = size_t(items[i].rect.pixels());
        if (linear && scene.exactBackground)  // the linear frame holds the background's own colour
            for (size_t p = 0; p < pixels; ++p)
                for (int k = 0; k < 3; ++k) rgbLinear[i][3 * p + size_t(k)] += (1.f - alpha[i][p]) * scene.background[k];
        if (linear)
            appendLinearPlane(rgbLinear[i], alpha[i], scene.transparentBackground, r.rgb.data() + r.layout.linearOffset(pixels));
        r.busySeconds = seconds * double(pixels) / double(std::max<int64_t>(1, totalPixels));
    }
    return out;
}

}  // namespace rf::farm
