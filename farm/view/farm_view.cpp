#include "farm_view.h"

#include <algorithm>
#include <cstring>
#include <thread>

#include "messages.h"

namespace rf::view {

FarmView::FarmView(farm::Transport& t, RenderSettings settings, int threadsPerRank, Publish publish)
    : t_(t), settings_(settings), threadsPerRank_(threadsPerRank), publish_(std::move(publish)) {
    const auto now = Clock::now();
    for (int r = 1; r < t_.size(); ++r) {
        inFlight_[r] = 0;
        heard_[r] = now;
    }
}

FarmView::~FarmView() {
    try {
        for (int r = 1; r < t_.size(); ++r) t_.send(r, farm::kTagStop, {});
        t_.flush(1.0);
    } catch (const farm::TransportError&) {
        // A rank is gone already; mpirun ends the rest.
    }
}

uint64_t FarmView::request(const ViewRequest& r) {
    request_ = r;
    ++epoch_;
    active_ = true;
    passes_ = r.moving ? std::vector<int>{1} : refinementSpp(settings_.spp);
    pass_ = 0;
    for (auto& [rank, n] : inFlight_) n = 0;  // their tiles are stale now; late ones are dropped
    startPass();
    return epoch_;
}

void FarmView::resumeAfterFilm() {
    // Tiles out before the film were dropped by the ranks; the film's messages were runFarm's.
    const auto now = Clock::now();
    for (auto& [rank, n] : inFlight_) n = 0;
    for (auto& [rank, when] : heard_) when = now;
    active_ = false;
}

std::string FarmView::findSilentRank(double seconds) {
    std::map<int, bool> answered;
    for (int r = 1; r < t_.size(); ++r) answered[r] = false;
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    while (Clock::now() < end) {
        farm::Message m;
        try {
            while (t_.poll(m))
                if (m.tag == farm::kTagHeartbeat && farm::decodeHeartbeat(m.bytes).signalled) answered[m.source] = true;
        } catch (const std::exception&) {
            // A failing receive says as much as silence.
        }
        if (std::all_of(answered.begin(), answered.end(), [](const auto& a) { return a.second; })) return "";
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    for (const auto& [rank, ok] : answered)
        if (!ok) return "rank " + std::to_string(rank);
    return "";
}

void FarmView::setTimeline(const anim::Timeline&, const std::string& timelineJson) {
    // Messages from rank 0 arrive in order, so the next work item already sees it.
    for (int r = 1; r < t_.size(); ++r) t_.send(r, farm::kTagViewTimeline, timelineJson);
}

void FarmView::startPass() {
    const int scale = request_.moving ? scale_ : 1;
    const int w = std::max(1, (settings_.width + scale - 1) / scale), h = std::max(1, (settings_.height + scale - 1) / scale);
    if (frame_.width != w || frame_.height != h) frame_.rgb.assign(size_t(w) * h * 3, 0);
    frame_.epoch = epoch_;
    frame_.width = w;
    frame_.height = h;
    frame_.spp = passes_[pass_];
    frame_.moving = request_.moving;
    frame_.camera = request_.camera;
    frame_.frame = request_.frame;
    frame_.input = request_.input;
    const int cols = (settings_.width + kTintTile - 1) / kTintTile, rows = (settings_.height + kTintTile - 1) / kTintTile;
    frame_.tileRank.assign(size_t(cols) * rows, 0);
    tiles_ = makeTiles(w, h, kWorkTile);
    nextTile_ = tilesDone_ = 0;
    passStart_ = lastPublish_ = Clock::now();
}

void FarmView::dispatch() {
    for (auto& [rank, n] : inFlight_) {
        while (n < kInFlightPerRank && nextTile_ < tiles_.size()) {
            ViewWork w;
            w.epoch = epoch_;
            w.frame = request_.frame;
            w.spp = passes_[pass_];
            w.width = frame_.width;
            w.height = frame_.height;
            w.followTimeline = request_.followTimeline ? 1 : 0;
            w.rect = tiles_[nextTile_++];
            w.camera = request_.camera;
            t_.send(rank, farm::kTagViewWork, encodeViewWork(w));
            ++n;
        }
    }
}

void FarmView::take(const farm::Message& m) {
    heard_[m.source] = Clock::now();
    if (m.tag == farm::kTagError) {
        error_ = "rank " + std::to_string(m.source) + ": " + m.bytes;
        return;
    }
    if (m.tag != farm::kTagViewTile) return;
    const ViewTile tile = decodeViewTile(m.bytes);
    if (tile.work.epoch != epoch_ || tile.work.spp != passes_[pass_] || tile.work.width != frame_.width) return;
    --inFlight_[m.source];
    frame_.camera = tile.work.camera;  // the timeline's camera when following it, as rendered
    const TileRect& r = tile.work.rect;
    for (int y = 0; y < r.height(); ++y)
        std::memcpy(&frame_.rgb[(size_t(r.y0 + y) * frame_.width + r.x0) * 3], &tile.rgb[size_t(y) * r.width() * 3],
                    size_t(r.width()) * 3);
    // Cells of the target-size grid this rectangle covers, for the rank tint.
    const int scale = (settings_.width + frame_.width - 1) / frame_.width;  // 1, 2 or 4
    const int cols = (settings_.width + kTintTile - 1) / kTintTile;
    for (int cy = r.y0 * scale / kTintTile; cy * kTintTile < r.y1 * scale && cy * kTintTile < settings_.height; ++cy)
        for (int cx = r.x0 * scale / kTintTile; cx * kTintTile < r.x1 * scale && cx < cols; ++cx)
            frame_.tileRank[size_t(cy) * cols + cx] = static_cast<uint8_t>(m.source);
    ++tilesDone_;
}

void FarmView::publishNow(bool complete) {
    ViewFrame copy = frame_;
    copy.complete = complete;
    copy.final = complete && (request_.moving || pass_ + 1 == passes_.size());
    copy.passMs = std::chrono::duration<double, std::milli>(Clock::now() - passStart_).count();
    publish_(std::move(copy));
    lastPublish_ = Clock::now();
}

void FarmView::finishPass() {
    publishNow(true);
    if (request_.moving) {
        scale_ = nextMovingScale(scale_, std::chrono::duration<double, std::milli>(Clock::now() - passStart_).count());
        active_ = false;
    } else if (++pass_ < passes_.size()) {
        startPass();
    } else {
        active_ = false;
    }
}

void FarmView::step() {
    if (stopped_) return;
    try {
        farm::Message m;
        while (t_.poll(m)) take(m);
        if (!error_.empty()) {
            stopped_ = true;
            return;
        }
        if (active_ && tilesDone_ == tiles_.size()) finishPass();
        if (active_) {
            dispatch();
            if (Clock::now() - lastPublish_ > std::chrono::milliseconds(150)) publishNow(false);
        }
        const auto now = Clock::now();
        for (const auto& [rank, n] : inFlight_)
            if (n > 0 && now - heard_[rank] > std::chrono::duration<double>(kSilenceSeconds)) {
                error_ = "rank " + std::to_string(rank) + " stopped answering";
                stopped_ = true;
            }
    } catch (const std::exception& e) {
        error_ = e.what();
        stopped_ = true;
    }
}

}  // namespace rf::view
