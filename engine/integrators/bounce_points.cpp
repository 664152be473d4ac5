// Surface points of the bounce cache: placed by area, oriented per side, found through a hash grid.
#include "engine/integrators/bounce_points.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "engine/integrators/material_gltf.h"
#include "engine/util/parallel.h"
#include "engine/scene/scene.h"

namespace rf {

namespace {

/// Van der Corput's radical inverse in base 2: the second coordinate of each point, so the
/// points of one triangle form a Hammersley set with the first (their place along the area).
float radicalInverse2(uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
    i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
    i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
    i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
    return std::min(float(i) * 0x1p-32f, 0x1.fffffep-1f);
}

/// One triangle of a mesh side and the area before it on that side. rot: which of its corners
/// comes first (the lowest position), so a triangle's points do not depend on where its index
/// list starts.
struct AreaEntry {
    double before = 0.0;
    float area = 0.f;
    uint32_t tri = 0;
    uint32_t rot = 0;
};

/// Bits of x spread to every third place (Morton order).
uint64_t spread3(uint64_t x) {
    x &= 0x1FFFFF;
    x = (x | x << 32) & 0x1F00000000FFFFull;
    x = (x | x << 16) & 0x1F0000FF0000FFull;
    x = (x | x << 8) & 0x100F00F00F00F00Full;
    x = (x | x << 4) & 0x10C30C30C30C30C3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
}

bool lowerPoint(const Vec3& a, const Vec3& b) {
    return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
}

/// A mesh's triangles of positive area, ordered along a Morton curve through their centroids
/// (ties by the lowest corner, then the index), each starting at its lowest corner: points
/// spread along this order's running area then depend on the surface, not on the order the
/// file lists its triangles or their corners in (a vertex-cache-optimised copy gets the same).
std::vector<AreaEntry> surfaceOrder(const TriangleMesh& mesh) {
    struct Keyed {
        uint64_t key;
        Vec3 low;
        AreaEntry e;
    };
    std::vector<Keyed> tris;
    tris.reserve(mesh.triangleCount());
    Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Vec3& p : mesh.positions)
        if (isFinite(p)) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const Vec3 extent = glm::max(hi - lo, Vec3(1e-30f));
    for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3 c[3] = {mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                           mesh.positions[mesh.indices[3 * t + 2]]};
        uint32_t rot = 0;
        for (uint32_t k = 1; k < 3; ++k)
            if (lowerPoint(c[k], c[rot])) rot = k;
        const Vec3 &p0 = c[rot], &p1 = c[(rot + 1) % 3], &p2 = c[(rot + 2) % 3];
        const float a = 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
        if (!(a > 0.f) || !std::isfinite(a)) continue;
        const Vec3 u = glm::clamp(((p0 + p1 + p2) / 3.f - lo) / extent, Vec3(0.f), Vec3(1.f)) * float(0x1FFFFF);
        const uint64_t key = spread3(uint64_t(u.x)) | spread3(uint64_t(u.y)) << 1 | spread3(uint64_t(u.z)) << 2;
        tris.push_back({key, c[rot], {0.0, a, t, rot}});
    }
    std::sort(tris.begin(), tris.end(), [](const Keyed& a, const Keyed& b) {
        if (a.key != b.key) return a.key < b.key;
        if (a.low != b.low) return lowerPoint(a.low, b.low);
        return a.e.tri < b.e.tri;
    });
    std::vector<AreaEntry> out;
    out.reserve(tris.size());
    for (const Keyed& k : tris) out.push_back(k.e);
    return out;
}

/// One side of one bounce mesh: its triangles' running area, and its points.
struct MeshSide {
    uint32_t mesh = 0;
    float side = 1.f;
    std::vector<AreaEntry> entries;
    double area = 0.0;
    uint32_t first = 0, count = 0;  ///< its points' indices
};

/// The fewest points a mesh side gets, whatever its share of the area: a small part next to a
/// large floor still has points of its own to read its bounce from.
constexpr uint32_t kMinPointsPerSide = 8;

}  // namespace

bool bounceSurface(const Scene& scene, int mesh) {
    const int mat = scene.geometry.meshes[size_t(mesh)].material;
    if (mat < 0 || size_t(mat) >= scene.materials.size()) return false;
    const Material& m = scene.materials[size_t(mat)];
    return m.gltfPbr && !m.unlit && (m.transmission < 1.f || m.metallic > 0.f);  // not all glass
}

/// The surface at barycentrics b of triangle (p0, p1, p2) of a bounce mesh, seen from the side
/// ng points to: found by a ray cast onto it, so it is the surface as the tracer resolves it.
bool castOnto(const Scene& scene, const Vec3& p0, const Vec3& p1, const Vec3& p2, const TriangleHit& b, const Vec3& ng,
              BouncePoint& bp) {
    Vec3 pError;
    const Vec3 p = triangleHitPoint(p0, p1, p2, b, pError);
    const float lift = 16.f * (glm::dot(absComponents(ng), pError) + gamma(7) * maxComponent(absComponents(p))) + 1e-30f;
    Ray r;
    r.o = p + lift * ng;
    r.d = -ng;
    r.tMax = 3.f * lift;
    Hit hit;
    if (!isFinite(r.o) || !scene.geometry.intersect(r, hit)) return false;
    bp.si = scene.geometry.interaction(r, hit);
    if (bp.si.mesh < 0 || !bounceSurface(scene, bp.si.mesh)) return false;
    bp.frame = shadingFrame(scene, bp.si, ng);
    const GltfSample gs = gltfSample(scene, bp.si);
    // A blended surface (alphaMode BLEND) reflects and glows with its covered share only.
    const float cover = gltfCoverage(scene, bp.si);
    bp.albedo = gs.surface.baseColor * (1.f - gs.surface.metallic) * (1.f - gs.transmission) * cover;
    bp.emission = gs.emission * cover;
    return true;
}

void BouncePoints::keep(const std::vector<uint8_t>& keep) {
    std::vector<BouncePoint> p, f;
    std::vector<uint32_t> start{0};
    for (size_t i = 0; i < points.size(); ++i) {
        if (!keep[i]) continue;
        p.push_back(points[i]);
        f.insert(f.end(), footprint.begin() + footprintStart[i], footprint.begin() + footprintStart[i + 1]);
        start.push_back(uint32_t(f.size()));
    }
    points = std::move(p);
    footprint = std::move(f);
    footprintStart = std::move(start);
}

BouncePoints placeBouncePoints(const Scene& scene, uint32_t count, int threads) {
    BouncePoints out;
    double& area = out.area;
    std::vector<MeshSide> sides;
    double total = 0.0;
    for (size_t m = 0; m < scene.geometry.meshes.size(); ++m) {
        if (!bounceSurface(scene, int(m))) continue;
        const TriangleMesh& mesh = scene.geometry.meshes[m];
        MeshSide ms;
        ms.mesh = uint32_t(m);
        ms.entries = surfaceOrder(mesh);
        for (AreaEntry& e : ms.entries) {
            e.before = ms.area;
            ms.area += e.area;
        }
        if (ms.entries.empty()) continue;
        sides.push_back(ms);
        total += ms.area;
        if (scene.materials[size_t(mesh.material)].doubleSided) {
            sides.push_back(std::move(ms));
            sides.back().side = -1.f;
            total += sides.back().area;
        }
    }
    area = total;
    if (sides.empty() || count == 0 || !(total > 0.0)) return out;
    // Each side's share of `count` by area, at least kMinPointsPerSide.
    uint32_t all = 0;
    for (MeshSide& ms : sides) {
        ms.first = all;
        ms.count = std::max(kMinPointsPerSide, uint32_t(std::lround(double(count) * ms.area / total)));
        all += ms.count;
    }
    constexpr uint32_t K = BouncePoints::kFootprint;
    std::vector<BouncePoint> placed(all), feet(size_t(all) * K);
    std::vector<uint8_t> ok(all, 0), footOk(size_t(all) * K, 0);
    std::vector<uint32_t> casts(all, 0);
    parallelFor(int(all), threads, [&](int index, int) {
        const uint32_t i = uint32_t(index);
        const MeshSide& ms = *std::prev(std::upper_bound(sides.begin(), sides.end(), i,
                                                         [](uint32_t v, const MeshSide& s) { return v < s.first; }));
        // Stratified along the side's running sum of areas: its k-th point in the middle of its share.
        const uint32_t k = i - ms.first;
        const double u = (double(k) + 0.5) / double(ms.count) * ms.area;
        auto it = std::upper_bound(ms.entries.begin(), ms.entries.end(), u, [](double v, const AreaEntry& e) { return v < e.before; });
        const AreaEntry& e = *(it == ms.entries.begin() ? it : it - 1);
        const float f = std::clamp(float((u - e.before) / double(e.area)), 0.f, 0x1.fffffep-1f);
        const float g = radicalInverse2(k);
        const TriangleMesh& mesh = scene.geometry.meshes[ms.mesh];
        const uint32_t* corner = &mesh.indices[3 * size_t(e.tri)];
        const Vec3& p0 = mesh.positions[corner[e.rot]];
        const Vec3& p1 = mesh.positions[corner[(e.rot + 1) % 3]];
        const Vec3& p2 = mesh.positions[corner[(e.rot + 2) % 3]];
        // Uniform over the triangle (the square-root map).
        const float s = std::sqrt(f);
        TriangleHit b;
        b.b1 = g * s;
        b.b2 = 1.f - s;
        b.b0 = 1.f - b.b1 - b.b2;
        const Vec3 e1 = p1 - p0, e2 = p2 - p0, n = glm::cross(e1, e2);
        const Vec3 ng = ms.side * glm::normalize(n);
        ++casts[i];
        if (!castOnto(scene, p0, p1, p2, b, ng, placed[i])) return;
        ok[i] = 1;
        // The footprint: a Vogel spiral on a disc about the point as large as its share of the
        // side's area (so the discs cover the surface as often as not: a shadow moving between
        // points is seen by some footprint), turned per point, kept where it stays on the triangle.
        const float rho = float(std::sqrt(ms.area / (double(kPi) * double(ms.count))));
        const Vec3 tu = glm::normalize(e1), tv = glm::normalize(glm::cross(n, e1));
        const Vec3 p = b.b0 * p0 + b.b1 * p1 + b.b2 * p2;
        const float d00 = glm::dot(e1, e1), d01 = glm::dot(e1, e2), d11 = glm::dot(e2, e2), den = d00 * d11 - d01 * d01;
        for (uint32_t j = 1; j < K; ++j) {
            const float radius = rho * std::sqrt((float(j) - 0.5f) / float(K - 1));
            const float angle = 2.39996323f * float(j) + 2.f * kPi * g;
            const Vec3 q = p + radius * (std::cos(angle) * tu + std::sin(angle) * tv) - p0;
            TriangleHit c;
            c.b1 = (d11 * glm::dot(q, e1) - d01 * glm::dot(q, e2)) / den;
            c.b2 = (d00 * glm::dot(q, e2) - d01 * glm::dot(q, e1)) / den;
            c.b0 = 1.f - c.b1 - c.b2;
            if (!(c.b0 >= 0.f && c.b1 >= 0.f && c.b2 >= 0.f)) continue;
            ++casts[i];
            footOk[size_t(i) * K + j] = castOnto(scene, p0, p1, p2, c, ng, feet[size_t(i) * K + j]);
        }
    });
    for (uint32_t i = 0; i < all; ++i) {
        out.rays += casts[i];
        if (!ok[i]) continue;
        out.points.push_back(placed[i]);
        out.footprint.push_back(placed[i]);
        for (uint32_t j = 1; j < K; ++j)
            if (footOk[size_t(i) * K + j]) out.footprint.push_back(feet[size_t(i) * K + j]);
        out.footprintStart.push_back(uint32_t(out.footprint.size()));
    }
    return out;
}

BounceGrid::BounceGrid(const std::vector<BouncePoint>& points, float radius)
    : points_(&points), radius_(radius), inv_(1.f / radius) {
    if (points.empty()) return;
    Vec3 lo(kInf);
    for (const BouncePoint& p : points) lo = glm::min(lo, p.si.p);
    origin_ = lo;
    std::vector<std::pair<uint64_t, uint32_t>> keyed(points.size());
    for (uint32_t i = 0; i < points.size(); ++i) {
        const Vec3 c = (points[i].si.p - origin_) * inv_;
        keyed[i] = {key(int(c.x), int(c.y), int(c.z)), i};
    }
    std::sort(keyed.begin(), keyed.end());
    order_.resize(keyed.size());
    for (uint32_t i = 0; i < keyed.size(); ++i) order_[i] = keyed[i].second;
    // A dense table of cells where the bounds allow (a look-up is then an index), else a hash
    // map of the occupied ones; either way a cell's points are in index order.
    Vec3 hi(-kInf);
    for (const BouncePoint& p : points) hi = glm::max(hi, p.si.p);
    const Vec3 span = glm::floor((hi - origin_) * inv_) + Vec3(1.f);
    if (isFinite(span) && double(span.x) * double(span.y) * double(span.z) <= double(kMaxDenseCells)) {
        dims_ = glm::ivec3(span);
        denseStart_.assign(size_t(dims_.x) * size_t(dims_.y) * size_t(dims_.z) + 1, 0);
        for (uint32_t i : order_) {
            const glm::ivec3 c((points[i].si.p - origin_) * inv_);
            ++denseStart_[dense(c.x, c.y, c.z) + 1];
        }
        for (size_t c = 1; c < denseStart_.size(); ++c) denseStart_[c] += denseStart_[c - 1];
        // order_ grouped by dense cell (the key's order is another), index order within.
        std::vector<uint32_t> fill(denseStart_.begin(), denseStart_.end() - 1), grouped(order_.size());
        for (uint32_t i = 0; i < points.size(); ++i) {
            const glm::ivec3 c((points[i].si.p - origin_) * inv_);
            grouped[fill[dense(c.x, c.y, c.z)]++] = i;
        }
        order_ = std::move(grouped);
        return;
    }
    for (uint32_t i = 0; i < keyed.size(); ++i) {
        auto [it, fresh] = cells_.try_emplace(keyed[i].first, i, i + 1);
        if (!fresh) it->second.second = i + 1;
    }
}

uint64_t BounceGrid::key(int x, int y, int z) const {
    // 21 bits a coordinate, offset so the cells just below the origin stay apart.
    auto c = [](int v) { return uint64_t(uint32_t(v + (1 << 20)) & 0x1FFFFFu); };
    return (c(x) << 42) | (c(y) << 21) | c(z);
}

template <class Visit>
void BounceGrid::forEachNear(const Vec3& p, float r, Visit&& visit) const {
    // The cells the ball of radius r about p overlaps (two a side while r is under a cell).
    const Vec3 lo = (p - origin_ - Vec3(r)) * inv_, hi = (p - origin_ + Vec3(r)) * inv_;
    if (!isFinite(lo) || !isFinite(hi) || maxComponent(absComponents(lo)) > float(1 << 19) ||
        maxComponent(absComponents(hi)) > float(1 << 19))
        return;
    glm::ivec3 c0(glm::floor(lo)), c1(glm::floor(hi));
    if (!denseStart_.empty()) {
        c0 = glm::max(c0, glm::ivec3(0));
        c1 = glm::min(c1, dims_ - glm::ivec3(1));
        for (int x = c0.x; x <= c1.x; ++x)
            for (int y = c0.y; y <= c1.y; ++y)
                for (int z = c0.z; z <= c1.z; ++z) {
                    const size_t c = dense(x, y, z);
                    for (uint32_t k = denseStart_[c]; k < denseStart_[c + 1]; ++k) visit(order_[k]);
                }
        return;
    }
    for (int x = c0.x; x <= c1.x; ++x)
        for (int y = c0.y; y <= c1.y; ++y)
            for (int z = c0.z; z <= c1.z; ++z) {
                const auto it = cells_.find(key(x, y, z));
                if (it == cells_.end()) continue;
                for (uint32_t k = it->second.first; k < it->second.second; ++k) visit(order_[k]);
            }
}

float BounceGrid::gather(const Vec3& p, const Vec3& n, float r, KernelWeights& out) const {
    const float r2 = r * r, invR2 = 1.f / r2, plane = 0.5f * r;
    float sum = 0.f;
    forEachNear(p, r, [&](uint32_t index) {
        const BouncePoint& q = (*points_)[index];
        const Vec3 d = p - q.si.p;
        const float d2 = glm::dot(d, d);
        if (!(d2 < r2)) return;
        const float facing = glm::dot(n, q.frame.ns);
        if (facing <= 0.f) return;
        const float off = glm::dot(d, q.frame.ng) / plane;
        if (off * off >= 1.f) return;
        const float a = 1.f - d2 * invR2, f2 = facing * facing;
        const float w = a * a * f2 * f2 * (1.f - off * off);
        if (!(w > 0.f)) return;
        out.emplace_back(index, w);
        sum += w;
    });
    return sum;
}

float BounceGrid::meanNeighbours() const {
    if (!points_ || points_->empty()) return 0.f;
    const std::vector<BouncePoint>& pts = *points_;
    const size_t step = std::max<size_t>(1, pts.size() / 256);
    size_t samples = 0, found = 0;
    const float r2 = radius_ * radius_;
    for (size_t i = 0; i < pts.size(); i += step, ++samples) {
        const Vec3 p = pts[i].si.p;
        forEachNear(p, radius_, [&](uint32_t index) {
            const Vec3 d = p - pts[index].si.p;
            found += glm::dot(d, d) < r2;
        });
    }
    return float(found) / float(std::max<size_t>(1, samples));
}

void BounceGrid::weights(const Vec3& p, const Vec3& n, KernelWeights& out, float scale, size_t most) const {
    out.clear();
    if (!points_ || order_.empty()) return;
    scale = std::clamp(scale, 0.f, 1.f);
    for (int reach = 1; reach <= 4; reach *= 2) {
        float sum = gather(p, n, radius_ * scale * float(reach), out);
        if (!(sum > 0.f)) {
            out.clear();
            continue;
        }
        if (out.size() > most) {
            // The strongest `most`, ties to the lower index: the same on every run.
            auto stronger = [](const auto& a, const auto& b) { return a.second > b.second || (a.second == b.second && a.first < b.first); };
            std::nth_element(out.begin(), out.begin() + std::ptrdiff_t(most), out.end(), stronger);
            out.resize(most);
            std::sort(out.begin(), out.end());
            sum = 0.f;
            for (const auto& e : out) sum += e.second;
        }
        for (auto& [index, w] : out) w /= sum;
        return;
    }
}

}  // namespace rf
