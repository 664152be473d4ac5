#include "engine/geometry/triangle4.h"

#include "engine/util/simd4.h"

namespace rf {

uint32_t watertightCandidates4(const WatertightRay& wr, const Triangle4& t) {
    // intersectTriangleWatertight's first half, lane by lane and operation by operation:
    // A = p0 - o, ax = A[kx] - sx·A[kz], u = cx·by − cy·bx, ...
    const int kx = wr.kx, ky = wr.ky, kz = wr.kz;
    const F4 ox = splat4(wr.o[kx]), oy = splat4(wr.o[ky]), oz = splat4(wr.o[kz]);
    const F4 sx = splat4(wr.sx), sy = splat4(wr.sy);
    F4 px[3], py[3];
    for (int k = 0; k < 3; ++k) {
        F4 x, y, z;
        __builtin_memcpy(&x, t.v[k][kx], sizeof x);
        __builtin_memcpy(&y, t.v[k][ky], sizeof y);
        __builtin_memcpy(&z, t.v[k][kz], sizeof z);
        const F4 az = z - oz;
        px[k] = (x - ox) - sx * az;
        py[k] = (y - oy) - sy * az;
    }
    const F4 u = px[2] * py[1] - py[2] * px[1];
    const F4 v = px[0] * py[2] - py[0] * px[2];
    const F4 w = px[1] * py[0] - py[1] * px[0];
    const F4 zero = splat4(0.f);
    const I4 neg = (u < zero) | (v < zero) | (w < zero);
    const I4 pos = (u > zero) | (v > zero) | (w > zero);
    // An edge function of exactly zero goes to the scalar test, which decides it in double.
    const I4 onEdge = (u == zero) | (v == zero) | (w == zero);
    return laneMask(~(neg & pos) | onEdge);
}

void LeafTriangles::build(const Bvh& bvh, const Vec3* slotVerts,
                          const std::function<bool(uint32_t)>& packable) {
    first_.assign(bvh.primIndex().size(), kNone);
    blocks_.clear();
    for (const Bvh4Node& n : bvh.nodes4())
        for (int c = 0; c < 4; ++c) {
            if (!((n.valid >> c) & 1u) || n.count[c] == 0) continue;
            const uint32_t begin = n.child[c], end = begin + n.count[c];
            bool all = true;
            if (packable)
                for (uint32_t s = begin; s < end && all; ++s) all = packable(s);
            if (!all) continue;
            first_[begin] = static_cast<uint32_t>(blocks_.size());
            for (uint32_t s = begin; s < end; s += 4) {
                Triangle4 b{};  // lanes past the leaf's end stay zero; callers mask them off
                for (uint32_t l = 0; l < 4 && s + l < end; ++l)
                    for (int k = 0; k < 3; ++k)
                        for (int a = 0; a < 3; ++a) b.v[k][a][l] = slotVerts[3 * (s + l) + k][a];
                blocks_.push_back(b);
            }
        }
}

}  // namespace rf
