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

inline I4 splatI4(int v) { return I4{v, v, v, v}; }

/// floor() lane by lane, exact for |x| < 2^31 (truncation, then one down where it rounded up).
inline F4 floor4(F4 x) {
    const F4 t = __builtin_convertvector(__builtin_convertvector(x, I4), F4);
    return t > x ? t - 1.f : t;
}

/// Square root lane by lane, correctly rounded (sqrtps where SSE is there), as std::sqrt.
inline F4 sqrt4(F4 x) {
#if defined(__SSE__)
    return __builtin_ia32_sqrtps(x);
#else
    return F4{__builtin_sqrtf(x[0]), __builtin_sqrtf(x[1]), __builtin_sqrtf(x[2]), __builtin_sqrtf(x[3])};
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
