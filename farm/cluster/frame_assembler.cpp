#include "farm/cluster/frame_assembler.h"

#include <cstring>
#include <stdexcept>
#include <string>

namespace rf::farm {

FrameAssembler::FrameAssembler(int width, int height, anim::FrameRanges order, anim::FrameRanges onDisk, PixelLayout layout)
    : width_(width), height_(height), layout_(layout), order_(std::move(order)), onDisk_(std::move(onDisk)), next_(order_.start()) {}

bool FrameAssembler::wanted(int frame) const {
    // Frames leave in increasing order: those below the next one have been popped.
    return !finished() && frame >= order_.at(next_) && order_.contains(frame) && !onDisk_.contains(frame);
}

bool FrameAssembler::add(const TileResult& r) {
    const TileRect& t = r.item.rect;
    const std::string where = "frame " + std::to_string(r.item.frame);
    if (!wanted(r.item.frame)) throw std::runtime_error(where + ": result for a frame not being rendered");
    if (t.x0 < 0 || t.y0 < 0 || t.x1 > width_ || t.y1 > height_ || t.width() <= 0 || t.height() <= 0)
        throw std::runtime_error(where + ": tile outside the image");
    if (!(r.layout == layout_)) throw std::runtime_error(where + ": tile has another pixel layout than the job's");
    if (r.rgb.size() != layout_.bytes(size_t(t.pixels()))) throw std::runtime_error(where + ": tile has the wrong pixel count");
    const size_t framePixels = size_t(width_) * height_;
    auto [it, fresh] = partial_.try_emplace(r.item.frame);
    Partial& p = it->second;
    if (fresh) {
        p.rgb.assign(layout_.bytes(framePixels), 0);
        p.covered.assign(framePixels, 0);
        p.remaining = 1LL * width_ * height_;
    }
    // Each plane row by row: the 8-bit plane, then the linear one if present.
    const size_t ch = size_t(layout_.channels), lin = 4 * sizeof(float);
    const uint8_t* srcLinear = r.rgb.data() + layout_.linearOffset(size_t(t.pixels()));
    uint8_t* dstLinear = p.rgb.data() + layout_.linearOffset(framePixels);
    for (int y = t.y0; y < t.y1; ++y) {
        uint8_t* cov = p.covered.data() + size_t(y) * width_ + t.x0;
        for (int x = 0; x < t.width(); ++x) {
            if (cov[x]) throw std::runtime_error(where + ": tile covers pixels already rendered");
            cov[x] = 1;
        }
        const size_t dstPixel = size_t(y) * width_ + t.x0, srcPixel = size_t(y - t.y0) * t.width();
        std::memcpy(p.rgb.data() + ch * dstPixel, r.rgb.data() + ch * srcPixel, ch * size_t(t.width()));
        if (layout_.linear) std::memcpy(dstLinear + lin * dstPixel, srcLinear + lin * srcPixel, lin * size_t(t.width()));
    }
    p.remaining -= t.pixels();
    return p.remaining == 0;
}

const std::vector<uint8_t>* FrameAssembler::completed(int frame) const {
    auto it = partial_.find(frame);
    return it != partial_.end() && it->second.remaining == 0 ? &it->second.rgb : nullptr;
}

const std::vector<uint8_t>* FrameAssembler::pixels(int frame) const {
    auto it = partial_.find(frame);
    return it != partial_.end() ? &it->second.rgb : nullptr;
}

bool FrameAssembler::popReady(ReadyFrame& out) {
    if (finished()) return false;
    const int f = order_.at(next_);
    if (onDisk_.contains(f)) {
        out = {f, true, {}};
        order_.advance(next_);
        ++popped_;
        return true;
    }
    auto it = partial_.find(f);
    if (it == partial_.end() || it->second.remaining > 0) return false;
    out = {f, false, std::move(it->second.rgb)};
    partial_.erase(it);
    order_.advance(next_);
    ++popped_;
    return true;
}

}  // namespace rf::farm
