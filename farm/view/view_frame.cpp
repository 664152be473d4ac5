#include "farm/view/view_frame.h"

#include <algorithm>
#include <cmath>

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

int MovingScale::next(double ms) {
    const int wanted = nextMovingScale(scale_, ms);
    if (wanted > scale_) {  // too slow: down now, and a step up that led here was premature
        if (justUp_) needed_ = std::min(kLongestRun, needed_ * 2);
        scale_ = wanted;
        fastRun_ = 0;
    } else if (wanted < scale_ && ++fastRun_ >= needed_) {
        scale_ = wanted;
        fastRun_ = 0;
        justUp_ = true;
        return scale_;
    } else if (wanted == scale_) {
        fastRun_ = 0;
    }
    justUp_ = false;
    return scale_;
}

}  // namespace rf::view
