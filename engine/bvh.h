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
    bool traverse(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const;

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
bool Bvh::traverse(const Ray& ray, float tMax, bool anyHit, LeafFn&& leaf) const {
    if (nodes_.empty()) return false;
    const RayBoxPrecomp pre(ray);
    const bool dirNeg[3] = {ray.d.x < 0.f, ray.d.y < 0.f, ray.d.z < 0.f};
    uint32_t stack[64];
    int sp = 0;
    uint32_t node = 0;
    bool hitAny = false;
    for (;;) {
        const BvhNode& n = nodes_[node];
        float tEntry;
        if (intersectAabb(n.box, pre, 0.f, tMax, tEntry)) {
            if (n.count > 0) {
                for (uint32_t i = 0; i < n.count; ++i) {
                    if (leaf(primIndex_[n.offset + i], tMax)) {
                        hitAny = true;
                        if (anyHit) return true;
                    }
                }
                if (sp == 0) break;
                node = stack[--sp];
            } else if (dirNeg[n.axis]) {
                stack[sp++] = node + 1;
                node = n.offset;
            } else {
                stack[sp++] = n.offset;
                node = node + 1;
            }
        } else {
            if (sp == 0) break;
            node = stack[--sp];
        }
    }
    return hitAny;
}

}  // namespace rf
