#pragma once
/// The triangles of each BVH leaf packed four at a time (structure of arrays), and a four-wide
/// pre-test with the edge functions of the watertight test. The pre-test only rules triangles
/// out, with the same float operations as intersectTriangleWatertight, so the scalar test stays
/// the one that decides a hit and results are bit for bit those of testing every triangle.
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/geometry/bvh.h"
#include "engine/geometry/triangle.h"

namespace rf {

/// Four triangles: v[vertex][axis][lane].
struct alignas(16) Triangle4 {
    float v[3][3][4];
};

/// Bit i set: lane i of t may be hit by the ray (its edge functions do not rule it out).
uint32_t watertightCandidates4(const WatertightRay& wr, const Triangle4& t);

/// Triangle4 blocks for the leaves of a Bvh whose slots all hold triangles.
class LeafTriangles {
public:
    static constexpr uint32_t kNone = ~0u;

    /// slotVerts: three vertices per slot (primIndex() order). packable(slot): the slot holds a
    /// triangle; a leaf with any other primitive gets no blocks. An empty packable: every slot
    /// holds a triangle (spares a call per slot on a tree rebuilt or refitted every frame).
    void build(const Bvh& bvh, const Vec3* slotVerts, const std::function<bool(uint32_t)>& packable);
    void build(const Bvh& bvh, const std::vector<Vec3>& slotVerts, const std::function<bool(uint32_t)>& packable) {
        build(bvh, slotVerts.data(), packable);
    }
    /// First block of the leaf that starts at slot, or kNone (test its slots one by one).
    uint32_t firstBlock(uint32_t slot) const { return slot < first_.size() ? first_[slot] : kNone; }
    const Triangle4& block(uint32_t i) const { return blocks_[i]; }

private:
    std::vector<uint32_t> first_;
    std::vector<Triangle4> blocks_;
};

}  // namespace rf
