#pragma once
/// Bounding volume hierarchy: binned SAH build (Wald 2007) and conservative ordered traversal.
#include <cstdint>
#include <vector>

#include "aabb.h"

namespace rf {

struct BvhNode {
    Aabb box;
    uint32_t offset = 0;  ///< leaf: first entry in primIndex; interior: index of the second child
    uint16_t count = 0;   ///< primitives in a leaf; 0 for an interior node (first child is next)
    uint8_t axis = 0;     ///< split axis of an interior node, for front-to-back order
};

class Bvh {
public:
    /// Builds over primitive bounds; an empty input gives an empty tree.
    void build(const std::vector<Aabb>& primBounds, int maxLeafSize = 4);

    /// Recomputes node boxes from moved primitives; the tree's topology stays.
    void refit(const std::vector<Aabb>& primBounds);

    bool empty() const { return nodes_.empty(); }
    const std::vector<BvhNode>& nodes() const { return nodes_; }
    const std::vector<uint32_t>& primIndex() const { return primIndex_; }
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
    bool traverseSlots(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const;

private:
    struct BuildItem {
        Aabb box;
        Vec3 centroid;
    };
    uint32_t buildRecursive(std::vector<BuildItem>& items, uint32_t begin, uint32_t end, int maxLeaf, int depth);

    std::vector<BvhNode> nodes_;
    std::vector<uint32_t> primIndex_;
};

template <typename LeafFn>
bool Bvh::traverseSlots(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const {
    if (nodes_.empty()) return false;
    const RayBoxPrecomp pre(ray);
    float tRoot;
    if (!intersectAabb(nodes_[0].box, pre, 0.f, tMax, tRoot)) return false;
    // Both children are tested at their parent: the nearer is visited first, the farther waits
    // on the stack with its entry distance and is dropped if a closer hit arrives meanwhile.
    struct Entry {
        uint32_t node;
        float tEntry;
    } stack[64];
    int sp = 0;
    uint32_t node = 0;
    bool hitAny = false;
    for (;;) {
        const BvhNode& n = nodes_[node];
        if (n.count > 0) {
            const uint32_t end = n.offset + n.count;
            for (uint32_t i = n.offset; i < end; ++i) {
                if (leaf(i, tMax)) {
                    hitAny = true;
                    if (anyHit) return true;
                }
            }
        } else {
            const uint32_t c0 = node + 1, c1 = n.offset;
            float t0, t1;
            const bool h0 = intersectAabb(nodes_[c0].box, pre, 0.f, tMax, t0);
            const bool h1 = intersectAabb(nodes_[c1].box, pre, 0.f, tMax, t1);
            if (h0 && h1) {
                if (t1 < t0) {
                    stack[sp++] = {c0, t0};
                    node = c1;
                } else {
                    stack[sp++] = {c1, t1};
                    node = c0;
                }
                continue;
            }
            if (h0 || h1) {
                node = h0 ? c0 : c1;
                continue;
            }
        }
        // Pop the next subtree that can still hold a hit closer than tMax.
        for (;;) {
            if (sp == 0) return hitAny;
            const Entry e = stack[--sp];
            if (e.tEntry <= tMax * (1.f + 2.f * gamma(3))) {  // entry carries rounding too
                node = e.node;
                break;
            }
        }
    }
}

}  // namespace rf
