#pragma once
/// Four-lane float vectors through GCC/Clang vector extensions: SSE2 on any x86-64, plain code
/// elsewhere. Shared by the BVH, the triangle and the sphere pre-tests.
#include <cstdint>

namespace rf {

typedef float F4 __attribute__((vector_size(16)));
typedef int I4 __attribute__((vector_size(16)));

inline F4 splat4(float v) { return F4{v, v, v, v}; }

/// a > b ? a : b lane by lane: a NaN in a keeps b (one maxps where SSE is there).
inline F4 maxKeep4(F4 a, F4 b) {
#if defined(__SSE__)
    return __builtin_ia32_maxps(a, b);
#else
    return a > b ? a : b;
#endif
}

/// a < b ? a : b lane by lane: a NaN in a keeps b (one minps where SSE is there).
inline F4 minKeep4(F4 a, F4 b) {
#if defined(__SSE__)
    return __builtin_ia32_minps(a, b);
#else
    return a < b ? a : b;
#endif
}

/// Lane signs as four bits (movmskps where SSE is there, a loop elsewhere).
inline uint32_t laneMask(I4 m) {
#if defined(__SSE__)
    return static_cast<uint32_t>(__builtin_ia32_movmskps(reinterpret_cast<F4>(m)));
#else
    uint32_t r = 0;
    for (int i = 0; i < 4; ++i) r |= uint32_t(m[i] & 1) << i;
    return r;
#endif
}

}  // namespace rf
