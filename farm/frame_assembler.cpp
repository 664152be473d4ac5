#include "frame_assembler.h"

#include <cstring>
#include <stdexcept>
#include <string>

namespace rf::farm {

FrameAssembler::FrameAssembler(int width, int height, std::vector<int> order, std::set<int> onDisk)
    : width_(width), height_(height), order_(std::move(order)), onDisk_(std::move(onDisk)) {
    for (int f : order_)
        if (!onDisk_.count(f)) wanted_.insert(f);
}

bool FrameAssembler::add(const TileResult& r) {
    const TileRect& t = r.item.rect;
    const std::string where = "frame " + std::to_string(r.item.frame);
    if (!wanted_.count(r.item.frame)) throw std::runtime_error(where + ": result for a frame not being rendered");
    if (t.x0 < 0 || t.y0 < 0 || t.x1 > width_ || t.y1 > height_ || t.width() <= 0 || t.height() <= 0)
        throw std::runtime_error(where + ": tile outside the image");
    if (r.rgb.size() != size_t(t.pixels()) * 3) throw std::runtime_error(where + ": tile has the wrong pixel count");
    auto [it, fresh] = partial_.try_emplace(r.item.frame);
    Partial& p = it->second;
    if (fresh) {
        p.rgb.assign(size_t(width_) * height_ * 3, 0);
        p.covered.assign(size_t(width_) * height_, 0);
        p.remaining = 1LL * width_ * height_;
    }
    for (int y = t.y0; y < t.y1; ++y) {
        uint8_t* cov = p.covered.data() + size_t(y) * width_ + t.x0;
        for (int x = 0; x < t.width(); ++x) {
            if (cov[x]) throw std::runtime_error(where + ": tile covers pixels already rendered");
            cov[x] = 1;
        }
        std::memcpy(p.rgb.data() + 3 * (size_t(y) * width_ + t.x0), r.rgb.data() + 3 * size_t(y - t.y0) * t.width(),
                    3 * size_t(t.width()));
    }
    p.remaining -= t.pixels();
    return p.remaining == 0;
}

const std::vector<uint8_t>* FrameAssembler::completed(int frame) const {
    auto it = partial_.find(frame);
    return it != partial_.end() && it->second.remaining == 0 ? &it->second.rgb : nullptr;
}

bool FrameAssembler::popReady(ReadyFrame& out) {
    if (next_ >= order_.size()) return false;
    const int f = order_[next_];
    if (onDisk_.count(f)) {
        out = {f, true, {}};
        ++next_;
        return true;
    }
    auto it = partial_.find(f);
    if (it == partial_.end() || it->second.remaining > 0) return false;
    out = {f, false, std::move(it->second.rgb)};
    partial_.erase(it);
    wanted_.erase(f);
    ++next_;
    return true;
}

}  // namespace rf::farm
