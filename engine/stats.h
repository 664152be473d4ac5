#pragma once
/// Ray counters by kind, summed per tile and per frame.
#include <cstdint>

namespace rf {

struct RayStats {
    uint64_t primary = 0;
    uint64_t shadow = 0;
    uint64_t reflection = 0;
    uint64_t refraction = 0;
    uint64_t nonFinite = 0;  ///< samples whose radiance was NaN/Inf, replaced by black

    uint64_t total() const { return primary + shadow + reflection + refraction; }
    RayStats& operator+=(const RayStats& o) {
        primary += o.primary;
        shadow += o.shadow;
        reflection += o.reflection;
        refraction += o.refraction;
        nonFinite += o.nonFinite;
        return *this;
    }
};

}  // namespace rf
