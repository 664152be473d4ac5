#pragma once
/// Random numbers that depend only on the work item (frame, pixel, sample): any rank, thread or
/// tile order gives the same picture.
#include <cstdint>

namespace rf {

/// Stateless 64-bit mixer (splitmix64 finaliser).
inline uint64_t mix64(uint64_t z) {
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/// The seed of one camera sample: a pure function of (frame, pixel, sample), never 0 (0 is
/// kNoSampleSeed, "take no random samples here").
inline uint64_t sampleSeed(uint64_t frame, uint64_t pixel, uint64_t sample) {
    return mix64(mix64(mix64(frame) ^ pixel) ^ sample) | 1u;
}
constexpr uint64_t kNoSampleSeed = 0;
/// A seed derived from seed for a sub-stream k (a ray spawned at some depth, a sample set);
/// kNoSampleSeed stays kNoSampleSeed.
inline uint64_t childSeed(uint64_t seed, uint64_t k) {
    return seed == kNoSampleSeed ? kNoSampleSeed : mix64(seed ^ (k * 0xD6E8FEB86659FD93ull)) | 1u;
}

class SampleRng {
public:
    SampleRng(uint64_t frame, uint64_t pixel, uint64_t sample)
        : state_(mix64(mix64(mix64(frame) ^ pixel) ^ sample)) {}
    explicit SampleRng(uint64_t seed) : state_(seed) {}
    /// Uniform in [0, 1).
    float next() {
        state_ = mix64(state_);
        return static_cast<float>(state_ >> 40) * (1.0f / 16777216.0f);
    }

private:
    uint64_t state_;
};

}  // namespace rf
