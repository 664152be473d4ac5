#pragma once
/// Bounding volume hierarchy: binned SAH build (Wald 2007), collapsed to a 4-wide tree whose
/// four child boxes are tested at once (GCC/Clang vector extensions: SSE2 on any x86-64), with
/// conservative, NaN-safe, front-to-back traversal.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/geometry/aabb.h"
#include "engine/util/simd4.h"

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
    /// Builds over primitive bounds; an empty input gives an empty tree. With pollCancel (a
    /// scene's load, never a render's rebuild) it calls pollLoadCancel as it goes.
    void build(const std::vector<Aabb>& primBounds, int maxLeafSize = 4, bool pollCancel = false);

    /// Recomputes node boxes from moved primitives; the tree's topology stays.
    void refit(const std::vector<Aabb>& primBounds);
    /// As refit(), from the boxes in slot order (slotBounds[s] the box of primitive
    /// primIndex()[s]), so a caller that keeps its primitives in leaf order reads them
    /// contiguously; and the 4-wide tree keeps the shape it had (collapsed from the boxes the
    /// tree was built or last refitted with) and only takes the new boxes: no new collapse.
    /// A tree without its 4-wide copy (dropWideNodes) collapses its current boxes first, so
    /// the shape is always that of the tree it was copied from.
    void refitBySlotKeepShape(const std::vector<Aabb>& slotBounds);

    /// The tree's surface area heuristic cost relative to its root box: Σ over interior nodes of
    /// area / root area, plus Σ over leaves of area / root area × primitives. A refitted tree
    /// whose primitives moved apart grows it; a fresh build of the same boxes does not.
    double sahCost() const;

    bool empty() const { return nodes_.empty(); }
    /// Frees the 4-wide copy (refit() makes it again): for a tree kept only as the topology a
    /// later refit starts from.
    void dropWideNodes() {
        std::vector<Bvh4Node>().swap(nodes4_);
        std::vector<uint32_t>().swap(wideFrom_);
    }
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

    /// Closest-hit traversal of a packet of n rays (at most kPacketMax) that share an origin:
    /// camera rays of neighbouring pixels. A node's four child boxes are tested against the
    /// packet's frustum (four side planes and a far plane behind the farthest hit so far) in
    /// one vector test, so a node costs the packet what it costs one ray. At a leaf each ray
    /// gets traverseLeaves's own box test (the same float operations, four rays at a time)
    /// with its own tMax, and leaf(ray, first, count, tMax[ray]) tests the primitives of the
    /// rays that pass. tMax: each ray's limit, lowered by leaf on a hit. Rays without a common
    /// origin, or spread over more than a hemisphere, are traced one by one.
    static constexpr int kPacketMax = 64;
    template <typename LeafFn>
    void traversePacket(const Ray* rays, int n, float* tMax, LeafFn&& leaf) const;

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
    /// refit()'s sweep: leafBox(first slot, count) gives a leaf's box; keepShape: the 4-wide
    /// nodes take the new boxes without a new collapse.
    template <typename LeafBox>
    void refitWith(LeafBox&& leafBox, bool keepShape);

    std::vector<BvhNode> nodes_;
    bool pollCancel_ = false;  ///< during build(): whether a load may stop it
    std::vector<Bvh4Node> nodes4_;
    /// Per 4-wide node, the binary node of each of its four children (~0u: none), so a refit
    /// can update the wide boxes without collapsing again.
    std::vector<uint32_t> wideFrom_;
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

namespace bvh_detail {
/// A packet's frustum: four side planes through the common origin o and the axis, with normals
/// pointing out; a box lies outside a plane when min over the box of (p − o)·n exceeds its limit
/// (0 for a side, the far limit for the axis).
struct PacketPlanes {
    F4 n[5][3];        ///< n[plane][axis], splat
    int corner[5][3];  ///< per plane and axis: 0 to read the box's lo, 3 its hi (the minimising corner)
    float axisDot[64];  ///< each ray's d·axis, for the far limit (lanes past the packet: 0)
};
/// Builds the frustum of n rays from rays[0].o: false if their origins differ or they spread
/// too far from their mean direction to bound this way (then they go one by one).
bool buildPacketPlanes(const Ray* rays, int n, PacketPlanes& pl);
}  // namespace bvh_detail

template <typename LeafFn>
void Bvh::traversePacket(const Ray* rays, int n, float* tMax, LeafFn&& leaf) const {
    static_assert(kPacketMax == 64, "PacketPlanes::axisDot");
    if (nodes4_.empty() || n <= 0) return;
    bvh_detail::PacketPlanes pl;
    if (n > kPacketMax || !bvh_detail::buildPacketPlanes(rays, n, pl)) {
        for (int i = 0; i < n; ++i)
            traverseLeaves(rays[i], tMax[i], false, [&](uint32_t first, uint32_t count, float& tm) {
                return leaf(i, first, count, tm);
            });
        return;
    }
    const int groups = (n + 3) / 4;
    // Per ray, four at a time, what traverseLeaves's lane computes for it. Lanes past n get an
    // empty interval (tMax −1 < 0) and never pass.
    alignas(16) float tm[kPacketMax];
    alignas(16) float inv[3][kPacketMax];
    alignas(16) int neg[3][kPacketMax];
    // The near slab of a group whose rays agree in the sign of 1/d on every axis (nearly all of
    // a camera packet): the offsets into a Bvh4Node's lo/hi block, as traverseLeaves keeps them;
    // -1 where the group's rays disagree (its lanes then choose the slab one by one).
    int nearOff[kPacketMax / 4][3];
    for (int i = 0; i < groups * 4; ++i) {
        const bool live = i < n;
        tm[i] = live ? tMax[i] : -1.f;
        for (int a = 0; a < 3; ++a) {
            inv[a][i] = live ? 1.f / rays[i].d[a] : inv[a][i & ~3];
            neg[a][i] = std::signbit(inv[a][i]) ? -1 : 0;
        }
    }
    for (int g = 0; g < groups; ++g)
        for (int a = 0; a < 3; ++a) {
            const int* s = neg[a] + 4 * g;
            nearOff[g][a] = (s[0] == s[1] && s[0] == s[2] && s[0] == s[3]) ? (s[0] ? 12 : 0) : -1;
        }
    const float widen = 1.f + 2.f * gamma(3);
    const F4 widenV = splat4(widen);
    F4 o[3];
    for (int a = 0; a < 3; ++a) o[a] = splat4(rays[0].o[a]);
    // The far plane: no ray of the packet can hit anything farther along the axis than its
    // farthest limit (t·(d·axis) for a hit at t), with a margin for rounding.
    auto farLimit = [&]() {
        F4 f = splat4(0.f);
        for (int g = 0; g < groups; ++g) {
            F4 t, d;
            __builtin_memcpy(&t, tm + 4 * g, sizeof t);
            __builtin_memcpy(&d, pl.axisDot + 4 * g, sizeof d);
            f = maxKeep4(t * d, f);
        }
        return std::max(std::max(f[0], f[1]), std::max(f[2], f[3])) * (1.f + 1e-5f);
    };
    float far = farLimit();
    struct Entry {
        uint32_t ref;    ///< interior: node index; leaf: first slot
        uint16_t count;  ///< 0: interior
        uint8_t slot;    ///< a leaf's place in its parent (where its box is)
        uint32_t parent;
        float key;       ///< min over the box of (p − o)·axis
    } stack[256];
    int sp = 0;
    Entry cur{0u, 0, 0, 0u, -kInf};
    for (;;) {
        if (cur.count > 0) {
            const float* box = &nodes4_[cur.parent].lo[0][0] + cur.slot;  // box[4·k]: lo x, y, z, hi x, y, z
            bool lowered = false;
            for (int g = 0; g < groups; ++g) {
                F4 t0 = splat4(0.f), t1;
                __builtin_memcpy(&t1, tm + 4 * g, sizeof t1);
                for (int a = 0; a < 3; ++a) {
                    F4 iv;
                    __builtin_memcpy(&iv, inv[a] + 4 * g, sizeof iv);
                    F4 near, farT;
                    if (nearOff[g][a] >= 0) {
                        near = (splat4(box[nearOff[g][a] + 4 * a]) - o[a]) * iv;
                        farT = (splat4(box[12 - nearOff[g][a] + 4 * a]) - o[a]) * iv;
                    } else {
                        I4 ng;
                        __builtin_memcpy(&ng, neg[a] + 4 * g, sizeof ng);
                        const F4 tLo = (splat4(box[4 * a]) - o[a]) * iv, tHi = (splat4(box[12 + 4 * a]) - o[a]) * iv;
                        near = ng ? tHi : tLo;
                        farT = ng ? tLo : tHi;
                    }
                    t0 = maxKeep4(near, t0);
                    t1 = minKeep4(farT * widenV, t1);
                }
                for (uint32_t m = laneMask(t0 <= t1); m; m &= m - 1) {
                    const int i = 4 * g + __builtin_ctz(m);
                    const float before = tm[i];
                    if (leaf(i, cur.ref, uint32_t(cur.count), tm[i]) && tm[i] < before) lowered = true;
                }
            }
            if (lowered) far = farLimit();
        } else {
            const Bvh4Node& node = nodes4_[cur.ref];
            const float* planes = &node.lo[0][0];
            F4 rel[6];  // lo − o (x, y, z), then hi − o, for the four children
            for (int k = 0; k < 6; ++k) {
                F4 b;
                __builtin_memcpy(&b, planes + 4 * k, sizeof b);
                rel[k] = b - o[k % 3];
            }
            F4 v[5];
            for (int k = 0; k < 5; ++k)
                v[k] = pl.n[k][0] * rel[pl.corner[k][0]] + pl.n[k][1] * rel[pl.corner[k][1] + 1] +
                       pl.n[k][2] * rel[pl.corner[k][2] + 2];
            const F4 zero = splat4(0.f);
            const I4 outside = (v[0] > zero) | (v[1] > zero) | (v[2] > zero) | (v[3] > zero) | (v[4] > splat4(far));
            uint32_t mask = laneMask(~outside) & node.valid;
            if (mask != 0) {
                const F4 key = v[4];
                auto entry = [&](int ch) {
                    return Entry{node.child[ch], node.count[ch], uint8_t(ch), cur.ref, key[ch]};
                };
                const int c0 = __builtin_ctz(mask);
                mask &= mask - 1;
                if (mask == 0) {
                    cur = entry(c0);
                    continue;
                }
                int idx[4] = {c0, 0, 0, 0}, k = 1;
                for (; mask; mask &= mask - 1) {
                    const int ch = __builtin_ctz(mask);
                    int j = k++;
                    for (; j > 0 && key[ch] > key[idx[j - 1]]; --j) idx[j] = idx[j - 1];
                    idx[j] = ch;
                }
                for (int i = 0; i < k - 1; ++i) stack[sp++] = entry(idx[i]);
                cur = entry(idx[k - 1]);
                continue;
            }
        }
        for (;;) {
            if (sp == 0) {
                for (int i = 0; i < n; ++i) tMax[i] = tm[i];
                return;
            }
            cur = stack[--sp];
            if (cur.key <= far) break;
        }
    }
}

}  // namespace rf
