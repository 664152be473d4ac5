#pragma once
/// Ray counters by kind, summed per tile and per frame.
#include <array>
#include <cstdint>

namespace rf {

struct RayStats {
    uint64_t primary = 0;
    uint64_t shadow = 0;
    uint64_t reflection = 0;
    uint64_t refraction = 0;
    uint64_t indirect = 0;   ///< sampled indirect light (RenderSettings::indirectSamples)
    uint64_t nonFinite = 0;  ///< samples whose radiance was NaN/Inf, replaced by black
    /// Rays that built and lit the bounce cache (bounce_cache.h), counted by the process that
    /// built it: not in total(), since each rank builds its own and how often depends on how
    /// the frames were spread over the ranks.
    uint64_t bounce = 0;

    uint64_t total() const { return primary + shadow + reflection + refraction + indirect; }
    RayStats& operator+=(const RayStats& o);
};

/// One counter of RayStats, with the name the --stats file gives it.
struct RayCounter {
    const char* name;
    uint64_t RayStats::*field;
};

/// Every counter, once. Summing, the stats file and the tests walk this list (the farm's wire
/// format copies the whole struct), so a counter added to RayStats needs one line here, and the
/// static_assert below refuses to build until it has it.
inline constexpr std::array<RayCounter, 7> kRayCounters{{
    {"primary", &RayStats::primary},
    {"shadow", &RayStats::shadow},
    {"reflection", &RayStats::reflection},
    {"refraction", &RayStats::refraction},
    {"indirect", &RayStats::indirect},
    {"non_finite_samples", &RayStats::nonFinite},
    {"bounce_cache", &RayStats::bounce},
}};
static_assert(sizeof(RayStats) == kRayCounters.size() * sizeof(uint64_t),
              "a RayStats counter is missing from kRayCounters (or a member is not a uint64_t counter)");

inline RayStats& RayStats::operator+=(const RayStats& o) {
    for (const RayCounter& c : kRayCounters) this->*c.field += o.*c.field;
    return *this;
}

}  // namespace rf
