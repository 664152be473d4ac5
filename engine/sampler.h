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

class SampleRng {
public:
    SampleRng(uint64_t frame, uint64_t pixel, uint64_t sample)
        : state_(mix64(mix64(mix64(frame) ^ pixel) ^ sample)) {}
    /// Uniform in [0, 1).
    float next() {
        state_ = mix64(state_);
        return static_cast<float>(state_ >> 40) * (1.0f / 16777216.0f);
    }

private:
    uint64_t state_;
};

}  // namespace rf
