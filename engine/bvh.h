#pragma once
/// Bounding volume hierarchy: binned SAH build (Wald 2007), collapsed to a 4-wide tree whose
/// four child boxes are tested at once (GCC/Clang vector extensions: SSE2 on any x86-64), with
/// conservative, NaN-safe, front-to-back traversal.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aabb.h"
#include "simd4.h"

namespace rf {

struct BvhNode {
    Aabb box;
    uint32_t offset = 0;  ///< leaf: first entry in primIndex; interior: index of the second child
    uint16_t count = 0;   ///< primitives in a leaf; 0 for an interior node (first child is next)
    uint8_t axis = 0;     ///< split axis of an interior node, for front-to-back order
};

/// Four children of a 4-wide node, boxes as structure of arrays for one vector test.
struct alignas(16) Bvh4Node {
    float lo[3][4];      ///< lo[axis][child]
    float hi[3][4];
    uint32_t child[4];   ///< interior: index in nodes4(); leaf: first slot in primIndex()
    uint16_t count[4];   ///< 0: interior child; > 0: leaf with this many primitives
    uint32_t valid = 0;  ///< bit i: child i exists
};
static_assert(offsetof(Bvh4Node, hi) == 12 * sizeof(float), "traversal reads lo and hi as one block");

class Bvh {
public:
    /// Builds over primitive bounds; an empty input gives an empty tree.
    void build(const std::vector<Aabb>& primBounds, int maxLeafSize = 4);

    /// Recomputes node boxes from moved primitives; the tree's topology stays.
    void refit(const std::vector<Aabb>& primBounds);

    bool empty() const { return nodes_.empty(); }
    const std::vector<BvhNode>& nodes() const { return nodes_; }
    const std::vector<uint32_t>& primIndex() const { return primIndex_; }
    const std::vector<Bvh4Node>& nodes4() const { return nodes4_; }
    Aabb bounds() const { return nodes_.empty() ? Aabb{} : nodes_[0].box; }

    /// Visits leaves front to back. leaf(prim, tMax) tests one primitive, lowers tMax on a hit
    /// and returns true if it hit. With anyHit the walk stops at the first hit.
    template <typename LeafFn>
    bool traverse(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const {
        return traverseSlots(ray, tMax, anyHit, [&](uint32_t slot, float& tm) { return leaf(primIndex_[slot], tm); });
    }

    /// As traverse, but leaf gets the slot (position in primIndex()) so callers can keep
    /// primitive data in leaf order and read it without an indirection.
    template <typename LeafFn>
    bool traverseSlots(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const {
        return traverseLeaves(ray, tMax, anyHit, [&](uint32_t first, uint32_t count, float& tm) {
            bool hit = false;
            for (uint32_t i = first; i < first + count; ++i) {
                if (leaf(i, tm)) {
                    hit = true;
                    if (anyHit) return true;
                }
            }
            return hit;
        });
    }

    /// As traverseSlots, but leaf(first, count, tMax) gets a whole leaf (slots first..first+count)
    /// and must test its primitives in slot order, so callers can test several at once.
    template <typename LeafFn>
    bool traverseLeaves(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const;

    /// Whether traverseLeaves's box test lets the ray through box before tMax: the same float
    /// operations as one lane of it (the near slab by the sign of 1/d, a NaN product skipped,
    /// the far distance widened). Rounding is monotone, so when a primitive's own box passes,
    /// every node box that holds it passes too, and the walk reaches the primitive's leaf.
    static bool boxPasses(const RayBoxPrecomp& pre, const Aabb& box, float tMax);

private:
    struct BuildItem {
        Aabb box;
        Vec3 centroid;
    };
    uint32_t buildRecursive(std::vector<BuildItem>& items, uint32_t begin, uint32_t end, int maxLeaf, int depth);
    /// Moves items[begin, end) whose centroid falls in bins 0..bin of axis before the others
    /// (primIndex_ alongside); returns the first of the others.
    uint32_t partition(std::vector<BuildItem>& items, uint32_t begin, uint32_t end, const Aabb& cbox, int axis, int bin);
    /// Collapses the binary tree into nodes4_ (children of a binary node's grandchildren).
    void collapse();
    uint32_t collapseNode(uint32_t node2);

    std::vector<BvhNode> nodes_;
    std::vector<Bvh4Node> nodes4_;
    std::vector<uint32_t> primIndex_;
};

inline bool Bvh::boxPasses(const RayBoxPrecomp& pre, const Aabb& box, float tMax) {
    const float widen = 1.f + 2.f * gamma(3);
    float t0 = 0.f, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const bool neg = std::signbit(pre.invD[a]);
        const float near = neg ? box.hi[a] : box.lo[a], far = neg ? box.lo[a] : box.hi[a];
        const float tNear = (near - pre.o[a]) * pre.invD[a];
        const float tFar = (far - pre.o[a]) * pre.invD[a] * widen;
        t0 = tNear > t0 ? tNear : t0;  // maxKeep4's lane: a NaN product keeps t0
        t1 = tFar < t1 ? tFar : t1;    // minKeep4's lane
    }
    return t0 <= t1;
}

template <typename LeafFn>
bool Bvh::traverseLeaves(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const {
    if (nodes4_.empty()) return false;
    const RayBoxPrecomp pre(ray);
    // Per axis, the slab the ray enters first: lo for a positive direction, hi for a negative
    // one (the sign of 1/d, so -0 counts as negative). (near − o)·inv ≤ (far − o)·inv then holds
    // for every box, so no per-box swap is needed; a NaN (0·inf, the origin on a slab of a
    // direction with a zero component) is skipped by maxKeep4/minKeep4 as by the scalar test.
    F4 o[3], inv[3];
    int nearOff[3], farOff[3];  // float offsets into a Bvh4Node's lo/hi block
    for (int a = 0; a < 3; ++a) {
        o[a] = splat4(pre.o[a]);
        inv[a] = splat4(pre.invD[a]);
        const bool neg = std::signbit(pre.invD[a]);
        nearOff[a] = 4 * a + (neg ? 12 : 0);
        farOff[a] = 4 * a + (neg ? 0 : 12);
    }
    const float widen = 1.f + 2.f * gamma(3);
    const F4 widenV = splat4(widen);
    // Entries: a node (count 0) or a leaf range, with the entry distance of its box.
    struct Entry {
        uint32_t ref;
        uint16_t count;
        float tEntry;
    } stack[256];
    int sp = 0;
    Entry cur{0u, 0, 0.f};
    bool hitAny = false;
    for (;;) {
        if (cur.count > 0) {
            if (leaf(cur.ref, uint32_t(cur.count), tMax)) {
                hitAny = true;
                if (anyHit) return true;
            }
        } else {
            const Bvh4Node& n = nodes4_[cur.ref];
            const float* planes = &n.lo[0][0];
            F4 t0 = splat4(0.f);
            F4 t1 = splat4(tMax);
            for (int a = 0; a < 3; ++a) {
                F4 near, far;
                __builtin_memcpy(&near, planes + nearOff[a], sizeof near);
                __builtin_memcpy(&far, planes + farOff[a], sizeof far);
                t0 = maxKeep4((near - o[a]) * inv[a], t0);
                t1 = minKeep4((far - o[a]) * inv[a] * widenV, t1);
            }
            uint32_t mask = laneMask(t0 <= t1) & n.valid;
            if (mask != 0) {
                auto entry = [&](int c) { return Entry{n.child[c], n.count[c], t0[c]}; };
                const int c0 = __builtin_ctz(mask);
                mask &= mask - 1;
                if (mask == 0) {  // one child hit: no ordering to do
                    cur = entry(c0);
                    continue;
                }
                // Nearest first; among equal entry distances the higher child index first, the
                // order of the stable descending insertion sort this replaces (ties between
                // equally near hits in different leaves resolve the same way).
                int idx[4] = {c0, 0, 0, 0}, k = 1;
                for (; mask; mask &= mask - 1) {
                    const int c = __builtin_ctz(mask);
                    int j = k++;
                    for (; j > 0 && t0[c] > t0[idx[j - 1]]; --j) idx[j] = idx[j - 1];
                    idx[j] = c;
                }
                // The farther ones wait on the stack; the nearest is visited now.
                for (int i = 0; i < k - 1; ++i) stack[sp++] = entry(idx[i]);
                cur = entry(idx[k - 1]);
                continue;
            }
        }
        // Pop the next subtree that can still hold a hit closer than tMax.
        for (;;) {
            if (sp == 0) return hitAny;
            cur = stack[--sp];
            if (cur.tEntry <= tMax * widen) break;
        }
    }
    return hitAny;
}

}  // namespace rf
