#include "anim/frame_time.h"

#include <algorithm>
#include <cmath>

namespace rf::anim {

int frameCount(double seconds, double fps) {
    const double n = std::round(seconds * fps);
    if (!(n >= 1.0)) return 1;
    return static_cast<int>(std::min(n, 1e9));
}

}  // namespace rf::anim
