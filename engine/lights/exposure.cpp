#include "engine/lights/exposure.h"

#include <algorithm>
#include <cmath>

namespace rf {

void ExposureMeter::add(const Image& img) {
    const size_t n = size_t(img.width()) * img.height();
    const float* p = img.data();
    for (size_t i = 0; i < n; ++i) {
        const float y = luminance(Color(p[3 * i], p[3 * i + 1], p[3 * i + 2]));
        if (!(y > 0.f) || !std::isfinite(y)) continue;
        logSum_ += std::log2(double(y));
        ++count_;
    }
}

float ExposureMeter::ev() const {
    if (count_ == 0) return 0.f;
    const double logAverage = logSum_ / double(count_);
    return float(std::clamp(std::log2(double(kMiddleGrey)) - logAverage, -20.0, 20.0));
}

}  // namespace rf
