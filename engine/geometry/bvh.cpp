#include "engine/geometry/bvh.h"

#include <algorithm>
#include <stdexcept>

#include "engine/util/load_control.h"

namespace rf {

namespace {
constexpr int kBins = 16;

/// The bin of a centroid's scaled offset, clamped as a float first: a huge extent or a tiny
/// span makes the offset inf (or NaN), which no int can hold (found by fuzz_gltf_text).
int binIndex(float f) { return f >= float(kBins - 1) ? kBins - 1 : f > 0.f ? static_cast<int>(f) : 0; }
constexpr float kTraversalCost = 1.0f;  // relative to one primitive test
constexpr int kMaxDepth = 62;           // traversal stack is 64 deep; deeper subtrees split by count
}  // namespace

void Bvh::build(const std::vector<Aabb>& primBounds, int maxLeafSize, bool pollCancel) {
    pollCancel_ = pollCancel;
    nodes_.clear();
    primIndex_.clear();
    if (primBounds.empty()) return;
    std::vector<BuildItem> items(primBounds.size());
    primIndex_.resize(primBounds.size());
    for (size_t i = 0; i < primBounds.size(); ++i) {
        items[i].box = primBounds[i];
        items[i].centroid = primBounds[i].center();
        primIndex_[i] = static_cast<uint32_t>(i);
    }
    nodes_.reserve(2 * primBounds.size());
    buildRecursive(items, 0, static_cast<uint32_t>(items.size()), maxLeafSize, 0);
    collapse();
}

void Bvh::collapse() {
    nodes4_.clear();
    wideFrom_.clear();
    if (nodes_.empty()) return;
    nodes4_.reserve(nodes_.size() / 2 + 1);
    wideFrom_.reserve(4 * (nodes_.size() / 2 + 1));
    collapseNode(0);
}

namespace {
/// A binary node's box as a lane of a 4-wide node. Traversal reads the near slab by the ray's
/// sign, so each lane needs lo ≤ hi: an inverted box is stored as the box the old per-box swap
/// tested, a NaN as all space.
inline void setWideLane(Bvh4Node& out, int i, const Aabb& box) {
    for (int a = 0; a < 3; ++a) {
        float lo = box.lo[a], hi = box.hi[a];
        if (lo > hi) std::swap(lo, hi);
        else if (!(lo <= hi)) lo = -kInf, hi = kInf;
        out.lo[a][i] = lo;
        out.hi[a][i] = hi;
    }
}
}  // namespace

uint32_t Bvh::collapseNode(uint32_t node2) {
    // Gather up to four binary descendants: open the interior child with the largest area
    // until four are reached or only leaves remain.
    uint32_t kids[4];
    int n = 0;
    if (nodes_[node2].count > 0) {
        kids[n++] = node2;  // a one-leaf tree
    } else {
        kids[n++] = node2 + 1;
        kids[n++] = nodes_[node2].offset;
        while (n < 4) {
            int best = -1;
            float bestArea = -1.f;
            for (int i = 0; i < n; ++i) {
                const BvhNode& c = nodes_[kids[i]];
                if (c.count == 0 && c.box.area() > bestArea) {
                    bestArea = c.box.area();
                    best = i;
                }
            }
            if (best < 0) break;
            const uint32_t open = kids[best];
            kids[best] = open + 1;
            kids[n++] = nodes_[open].offset;
        }
    }
    const uint32_t me = static_cast<uint32_t>(nodes4_.size());
    nodes4_.emplace_back();
    wideFrom_.insert(wideFrom_.end(), {kids[0], n > 1 ? kids[1] : ~0u, n > 2 ? kids[2] : ~0u, n > 3 ? kids[3] : ~0u});
    Bvh4Node out{};
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 4; ++c) {
            out.lo[a][c] = 0.f;
            out.hi[a][c] = 0.f;
        }
    out.valid = 0;
    for (int i = 0; i < n; ++i) {
        const BvhNode& c = nodes_[kids[i]];
        setWideLane(out, i, c.box);
        out.valid |= 1u << i;
        if (c.count > 0) {
            out.child[i] = c.offset;
            out.count[i] = c.count;
        } else {
            out.count[i] = 0;
            out.child[i] = collapseNode(kids[i]);
        }
    }
    nodes4_[me] = out;
    return me;
}

template <typename LeafBox>
void Bvh::refitWith(LeafBox&& leafBox, bool keepShape) {
    if (keepShape && nodes4_.empty()) collapse();  // the shape of the boxes it has now
    // Children always sit after their parent, so a reverse sweep sees children first.
    for (size_t i = nodes_.size(); i-- > 0;) {
        BvhNode& n = nodes_[i];
        Aabb b;
        if (n.count > 0) {
            b = leafBox(n.offset, n.count);
        } else {
            b.grow(nodes_[i + 1].box);
            b.grow(nodes_[n.offset].box);
        }
        n.box = b;
    }
    if (!keepShape) {
        collapse();
        return;
    }
    for (size_t w = 0; w < nodes4_.size(); ++w)
        for (int i = 0; i < 4; ++i)
            if (wideFrom_[4 * w + size_t(i)] != ~0u) setWideLane(nodes4_[w], i, nodes_[wideFrom_[4 * w + size_t(i)]].box);
}

void Bvh::refit(const std::vector<Aabb>& primBounds) {
    refitWith([&](uint32_t first, uint32_t count) {
        Aabb b;
        for (uint32_t k = 0; k < count; ++k) b.grow(primBounds[primIndex_[first + k]]);
        return b;
    }, false);
}

void Bvh::refitBySlotKeepShape(const std::vector<Aabb>& slotBounds) {
    refitWith([&](uint32_t first, uint32_t count) {
        Aabb b;
        for (uint32_t k = 0; k < count; ++k) b.grow(slotBounds[first + k]);
        return b;
    }, true);
}

double Bvh::sahCost() const {
    if (nodes_.empty()) return 0.0;
    const double root = nodes_[0].box.area();
    if (!(root > 0.0) || !std::isfinite(root)) return 0.0;
    double cost = 0.0;
    for (const BvhNode& n : nodes_) cost += double(n.box.area()) / root * (n.count > 0 ? double(n.count) : 1.0);
    return cost;
}

namespace {

/// The cheapest binned SAH split of items[begin, end): the bin boundary (split after bin `bin`
/// on `axis`) and its cost, sum of child area × count. bin < 0: no axis has two non-empty sides.
struct SahSplit {
    int axis = 0;
    int bin = -1;
    float cost = kInf;
};

template <typename Item>
SahSplit findSahSplit(const std::vector<Item>& items, uint32_t begin, uint32_t end, const Aabb& cbox, int defaultAxis) {
    SahSplit best;
    best.axis = defaultAxis;
    struct Bin {
        Aabb box;
        uint32_t n = 0;
    } bins[3][kBins];
    Vec3 scale3(0.f);
    for (int ax = 0; ax < 3; ++ax) {
        const float span = cbox.hi[ax] - cbox.lo[ax];
        scale3[ax] = (span > 0.f && std::isfinite(span)) ? kBins / span : 0.f;
    }
    // One pass over the items fills the bins of all three axes.
    for (uint32_t i = begin; i < end; ++i) {
        for (int ax = 0; ax < 3; ++ax) {
            const int bi = binIndex((items[i].centroid[ax] - cbox.lo[ax]) * scale3[ax]);
            bins[ax][bi].box.grow(items[i].box);
            ++bins[ax][bi].n;
        }
    }
    for (int ax = 0; ax < 3; ++ax) {
        if (scale3[ax] == 0.f) continue;  // all centroids share this coordinate
        float rightArea[kBins];
        uint32_t rightCount[kBins];
        Aabb acc;
        uint32_t n = 0;
        for (int i = kBins - 1; i > 0; --i) {
            acc.grow(bins[ax][i].box);
            n += bins[ax][i].n;
            rightArea[i] = acc.area();
            rightCount[i] = n;
        }
        acc = Aabb{};
        n = 0;
        for (int i = 0; i < kBins - 1; ++i) {
            acc.grow(bins[ax][i].box);
            n += bins[ax][i].n;
            if (n == 0 || rightCount[i + 1] == 0) continue;
            const float cost = acc.area() * n + rightArea[i + 1] * rightCount[i + 1];
            if (cost < best.cost) {  // strict: ties keep the earlier axis, so builds are deterministic
                best.cost = cost;
                best.bin = i;
                best.axis = ax;
            }
        }
    }
    return best;
}

}  // namespace

uint32_t Bvh::partition(std::vector<BuildItem>& items, uint32_t begin, uint32_t end, const Aabb& cbox, int axis, int bin) {
    const float lo = cbox.lo[axis], scale = kBins / (cbox.hi[axis] - lo);
    uint32_t* idx = primIndex_.data();
    // Items and their primitive indices move together.
    uint32_t l = begin, r = end;
    while (l < r) {
        if (binIndex((items[l].centroid[axis] - lo) * scale) <= bin) {
            ++l;
        } else {
            --r;
            std::swap(items[l], items[r]);
            std::swap(idx[l], idx[r]);
        }
    }
    return l;
}

uint32_t Bvh::buildRecursive(std::vector<BuildItem>& items, uint32_t begin, uint32_t end, int maxLeaf, int depth) {
    const uint32_t nodeIndex = static_cast<uint32_t>(nodes_.size());
    if (pollCancel_ && nodeIndex % 1024 == 0) pollLoadCancel();
    nodes_.emplace_back();
    Aabb box, cbox;
    for (uint32_t i = begin; i < end; ++i) {
        box.grow(items[i].box);
        cbox.grow(items[i].centroid);
    }
    nodes_[nodeIndex].box = box;
    const uint32_t count = end - begin;
    auto makeLeaf = [&] {
        nodes_[nodeIndex].offset = begin;
        nodes_[nodeIndex].count = static_cast<uint16_t>(count);
        return nodeIndex;
    };
    if (count <= 1) return makeLeaf();

    // Binned SAH over all three centroid axes; the cheapest split wins.
    int axis = cbox.longestAxis();
    uint32_t mid = begin;
    const float spanLongest = cbox.hi[axis] - cbox.lo[axis];
    if (spanLongest > 0.f && std::isfinite(spanLongest) && depth < kMaxDepth - 16) {
        const SahSplit split = findSahSplit(items, begin, end, cbox, axis);
        axis = split.axis;
        const float leafCost = box.area() * count;
        const float splitCost = kTraversalCost * box.area() + split.cost;
        if (split.bin >= 0 && (splitCost < leafCost || count > static_cast<uint32_t>(maxLeaf)))
            mid = partition(items, begin, end, cbox, axis, split.bin);
        else if (count <= static_cast<uint32_t>(maxLeaf))
            return makeLeaf();
    } else if (count <= static_cast<uint32_t>(maxLeaf)) {
        return makeLeaf();
    }
    if (mid == begin || mid == end) {
        // All centroids coincide (or SAH found no split) but the leaf is too big: split by count.
        if (count <= static_cast<uint32_t>(maxLeaf) * 4 || depth >= kMaxDepth) return makeLeaf();
        mid = begin + count / 2;
    }
    nodes_[nodeIndex].axis = static_cast<uint8_t>(axis);
    buildRecursive(items, begin, mid, maxLeaf, depth + 1);
    const uint32_t second = buildRecursive(items, mid, end, maxLeaf, depth + 1);
    nodes_[nodeIndex].offset = second;
    nodes_[nodeIndex].count = 0;
    return nodeIndex;
}

}  // namespace rf

namespace rf::bvh_detail {

bool buildPacketPlanes(const Ray* rays, int n, PacketPlanes& pl) {
    const Vec3 o = rays[0].o;
    Vec3 sum(0.f);
    for (int i = 0; i < n; ++i) {
        if (rays[i].o != o) return false;
        sum += rays[i].d;
    }
    const float len = glm::length(sum);
    if (!(len > 0.f) || !std::isfinite(len)) return false;
    const Vec3 axis = sum / len;
    // Any unit vector across the axis, then the third by the cross product.
    const Vec3 helper = std::abs(axis.x) < 0.9f ? Vec3(1.f, 0.f, 0.f) : Vec3(0.f, 1.f, 0.f);
    const Vec3 u = glm::normalize(glm::cross(axis, helper)), v = glm::cross(axis, u);
    float uLo = kInf, uHi = -kInf, vLo = kInf, vHi = -kInf;
    for (int i = 0; i < n; ++i) {
        const Vec3& d = rays[i].d;
        const float da = glm::dot(d, axis);
        // Within about 87 degrees of the axis, so the slopes below stay bounded (at most 20).
        if (!(da > 0.f && da * da > 0.0025f * glm::dot(d, d))) return false;
        pl.axisDot[i] = da;
        const float r = 1.f / da, su = glm::dot(d, u) * r, sv = glm::dot(d, v) * r;
        uLo = std::min(uLo, su), uHi = std::max(uHi, su);
        vLo = std::min(vLo, sv), vHi = std::max(vHi, sv);
    }
    for (int i = n; i < 64; ++i) pl.axisDot[i] = 0.f;
    // Widened far beyond the float error of the slopes and of the plane tests (a few ulps of
    // the distance): culling may only drop boxes that no ray of the packet comes near.
    const float margin = 1e-5f;
    uLo -= margin * (1.f + std::abs(uLo)), uHi += margin * (1.f + std::abs(uHi));
    vLo -= margin * (1.f + std::abs(vLo)), vHi += margin * (1.f + std::abs(vHi));
    const Vec3 normals[5] = {u - uHi * axis, uLo * axis - u, v - vHi * axis, vLo * axis - v, axis};
    for (int k = 0; k < 5; ++k)
        for (int a = 0; a < 3; ++a) {
            pl.n[k][a] = splat4(normals[k][a]);
            // (p − o)·n is least at the box corner with lo where n is positive, hi where not.
            pl.corner[k][a] = normals[k][a] >= 0.f ? 0 : 3;
        }
    return true;
}

}  // namespace rf::bvh_detail
