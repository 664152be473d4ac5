// The bounce cache: gather and node weights once per geometry, lighting once per light set.
#include "engine/integrators/bounce_cache.h"

#include <algorithm>
#include <cstring>
#include <mutex>

#include "engine/integrators/bounce_points.h"
#include "engine/materials/hemisphere.h"
#include "engine/integrators/light_eval.h"
#include "engine/materials/material_eval.h"
#include "engine/integrators/material_gltf.h"
#include "engine/util/parallel.h"
#include "engine/util/sampler.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"

namespace rf {

namespace {
/// Gather rays per point: the kernel then averages some 16 points' gathers, so the bounce at a
/// vertex rests on a few hundred rays (the report's --sweep-bounce trades points, not rays).
constexpr uint32_t kGatherRays = 32;
/// Points a kernel reaches on a flat surface (sets the radius from the area and the count).
constexpr float kPointsPerKernel = 16.f;
/// Where a gather ray lands, the radiance is read from the points within this share of the
/// radius (a quarter of them): the ray's own mean over 32 directions smooths it further, and
/// the transfer matrix stays a few entries a ray.
constexpr float kLandingScale = 0.5f;
constexpr size_t kLandingMost = 4;
/// The points' gathered values are smoothed over the whole kernel (at most this many points),
/// and each node then reads the few strongest points of a slightly smaller one: a vertex's value
/// is as smooth as the points', at a few multiplications a vertex per light change.
constexpr size_t kSmoothMost = 24;
constexpr float kNodeScale = 0.75f;
constexpr size_t kNodeMost = 6;
/// A point whose gather meets this share of back faces lies inside closed geometry (the inner
/// side of a double-sided sphere, a floor under a box): it is dropped.
constexpr float kInsideShare = 0.3f;
/// Glass surfaces a gather ray looks through before it gives up.
constexpr int kGlassCrossings = 4;
/// Bounces: the second costs one more sparse product per light change.
constexpr int kBounces = 2;
/// Triangle grids: at most this many nodes along an edge, and in all this many per point (past
/// it their spacing grows: the nodes cannot hold more detail than the points anyway).
constexpr uint32_t kMaxGridSide = 64;
constexpr size_t kGridNodesPerPoint = 16;

/// A sparse matrix in compressed rows, with Color or float values, kept in parts of up to
/// kChunk rows (each part its own compressed rows): parts are built in parallel and kept as
/// they are, so a matrix with a row per vertex of a big model is never copied whole to join them.
template <class T>
struct Sparse {
    static constexpr size_t kChunk = 256;
    struct Part {
        size_t first = 0;                ///< its first row in the matrix
        std::vector<uint32_t> start{0};  ///< its rows' starts in col and val, and the end
        std::vector<uint32_t> col;
        std::vector<T> val;
    };
    std::vector<Part> parts;
    size_t count = 0;
    size_t rows() const { return count; }
    /// out[r] = Σ val × in[col] (Color in; T scales it).
    void apply(const std::vector<Color>& in, std::vector<Color>& out, int threads) const {
        out.assign(rows(), Color(0.f));
        parallelFor(int(parts.size()), threads, [&](int c, int) {
            const Part& part = parts[size_t(c)];
            for (size_t r = 0; r + 1 < part.start.size(); ++r) {
                Color s(0.f);
                for (uint32_t k = part.start[r]; k < part.start[r + 1]; ++k) s += part.val[k] * in[part.col[k]];
                out[part.first + r] = s;
            }
        });
    }
    /// Appends n rows, row r made by fill(r, row, w) (row empty on entry; w a scratch list of
    /// kernel weights to reuse), a part of up to kChunk rows at a time in parallel.
    template <class Fill>
    void appendRows(size_t n, int threads, Fill fill) {
        const size_t first = parts.size();
        parts.resize(first + (n + kChunk - 1) / kChunk);
        parallelFor(int(parts.size() - first), threads, [&](int c, int) {
            Part& part = parts[first + size_t(c)];
            part.first = count + size_t(c) * kChunk;
            std::vector<std::pair<uint32_t, T>> row;
            KernelWeights w;
            for (size_t r = size_t(c) * kChunk; r < std::min(n, size_t(c + 1) * kChunk); ++r) {
                row.clear();
                fill(r, row, w);
                for (const auto& [cc, v] : row) part.col.push_back(cc), part.val.push_back(v);
                part.start.push_back(uint32_t(part.col.size()));
            }
            part.col.shrink_to_fit();
            part.val.shrink_to_fit();
        });
        count += n;
    }
};

/// Where a gather ray landed: the surface point and its normal towards the ray's origin, and
/// what the glass it crossed lets through.
struct GatherHit {
    Vec3 p{0.f}, n{0.f};
    Color through{1.f};
};

/// The nodes of one mesh: a value per vertex for each side that has one, and a triangle grid
/// for triangles wider than the kernel.
struct MeshNodes {
    int64_t front = -1, back = -1;  ///< node of vertex 0 on each side (−1: none)
    std::vector<uint32_t> grid;     ///< per triangle: index into BounceGeometry::grids, or ~0u
};

/// The regular grid of one large triangle: (L+1)(L+2)/2 nodes a side, node (a, b) at
/// barycentrics (1 − a/L − b/L, a/L, b/L), stored row by row in a.
struct TriGrid {
    uint32_t L = 1;
    int64_t front = -1, back = -1;
};

uint32_t gridIndex(uint32_t L, uint32_t a, uint32_t b) { return a * (L + 1) - a * (a - 1) / 2 + b; }

uint64_t hashBytes(uint64_t h, const void* data, size_t n) {
    const unsigned char* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001B3ull;
    return h;
}

/// Everything about the lights that the cache's lighting reads.
uint64_t lightsKey(const Scene& scene) {
    uint64_t h = 0xCBF29CE484222325ull;
    for (const Light& L : scene.lights) {
        const float f[] = {L.position.x,  L.position.y,    L.position.z,    L.direction.x,   L.direction.y,
                           L.direction.z, L.color.r,       L.color.g,       L.color.b,       L.intensity,
                           L.attenuation.x, L.attenuation.y, L.attenuation.z, L.innerCone,   L.outerCone,
                           L.range,       float(L.type),   L.castShadows ? 1.f : 0.f};
        h = hashBytes(h, f, sizeof f);
    }
    return h;
}

/// Everything about the materials that the cache's points keep (albedo, emission, what glass
/// passes): an animation that keys a material's factors makes the points again.
uint64_t materialsKey(const Scene& scene) {
    uint64_t h = 0xCBF29CE484222325ull;
    auto transform = [&](const TextureTransform& t) {
        const float f[] = {t.offset.x, t.offset.y, t.rotation, t.scale.x, t.scale.y};
        h = hashBytes(h, f, sizeof f);
    };
    for (const Material& m : scene.materials) {
        const float f[] = {m.color.r,        m.color.g,          m.color.b,         m.alpha,          m.alphaCutoff,
                           m.metallic,       m.roughness,        m.specularWeight,  m.emission.r,     m.emission.g,
                           m.emission.b,     m.transmission,     m.ior,             m.thickness,      m.attenuation.r,
                           m.attenuation.g,  m.attenuation.b,    m.sheenColor.r,    m.sheenColor.g,   m.sheenColor.b,
                           m.sheenRoughness, m.clearcoat,        m.clearcoatRoughness, m.occlusionStrength,
                           m.normalScale,    m.clearcoatNormalScale};
        h = hashBytes(h, f, sizeof f);
        for (const TextureTransform* t :
             {&m.baseColorTransform, &m.normalTransform, &m.metallicRoughnessTransform, &m.occlusionTransform, &m.emissiveTransform,
              &m.clearcoatTransform, &m.clearcoatRoughnessTransform, &m.clearcoatNormalTransform, &m.specularGlossinessTransform,
              &m.sheenColorTransform, &m.sheenRoughnessTransform, &m.thicknessTransform})
            transform(*t);
    }
    return h;
}

}  // namespace

struct BounceGeometry {
    std::vector<BouncePoint> points;
    BounceGrid grid;
    Sparse<Color> transfer;  ///< point -> point: the gather (1/rays folded in)
    Sparse<float> smooth;    ///< point <- points: the kernel over the points' gathered values
    /// Where each point's direct light is measured (BouncePoints' footprints).
    std::vector<BouncePoint> footprint;
    std::vector<uint32_t> footprintStart{0};
    Sparse<float> nodeWeights;  ///< node <- points
    std::vector<MeshNodes> meshes;
    std::vector<TriGrid> grids;
    uint64_t rays = 0;  ///< traced to build it (placing the points, their gathers)
};

/// What bounceCache keeps in a job's slot (RenderView::bounceSlot).
struct BounceSlot {
    uint64_t geometryVersion = 0;
    uint64_t materials = 0;  ///< materialsKey of the scene the geometry was made from
    uint32_t points = 0;
    std::shared_ptr<const BounceGeometry> geometry;
    bool triedLit = false;  ///< the geometry was looked at with lights in the scene
    /// The geometry lit under the last few sets of lights (keyed by lightsKey), most recent
    /// first: a rank handed tiles of two frames in turn (pixel mode) lights each frame once.
    std::vector<std::pair<uint64_t, std::shared_ptr<const BounceCache>>> lit;
    static constexpr size_t kLitKept = 4;
};

uint32_t bouncePoints(const RenderSettings& settings) { return uint32_t(std::max(0, settings.bounce)) * 1000u; }

namespace {

/// The gather of point i: kGatherRays cosine-distributed rays from its side, through glass,
/// to the first opaque surface. backFaces: how many met a surface from behind.
std::vector<GatherHit> gatherPoint(const Scene& scene, const BouncePoint& bp, uint32_t i, int& backFaces, uint64_t& rays) {
    std::vector<GatherHit> hits;
    hits.reserve(kGatherRays);
    backFaces = 0;
    SampleRng rng(mix64(0xB0C3ull ^ i));
    const Vec2 rot(rng.next(), rng.next());
    Vec3 t, b;
    orthonormalBasis(bp.frame.ns, t, b);
    const Vec3 pad(gamma(7) * maxComponent(absComponents(bp.si.p)));
    for (uint32_t k = 0; k < kGatherRays; ++k) {
        const Vec3 l = cosineHemisphere(stratifiedPoint(k, kGatherRays, rot));
        Vec3 dir = l.x * t + l.y * b + l.z * bp.frame.ns;
        const float below = glm::dot(dir, bp.frame.ng);
        if (below <= 0.f) dir = glm::normalize(dir - 2.f * below * bp.frame.ng);
        Ray r;
        uint32_t skip = scene.geometry.skipFor(bp.si, dir);
        r.o = skip == bp.si.prim ? bp.si.p : offsetRayOrigin(bp.si.p, bp.si.pError + pad, bp.frame.ng, dir);
        r.d = dir;
        GatherHit g;
        for (int crossing = 0; crossing <= kGlassCrossings; ++crossing) {
            Hit hit;
            ++rays;
            if (!scene.geometry.intersect(r, hit, skip)) break;
            const SurfaceInteraction hs = scene.geometry.interaction(r, hit);
            const Material& m = scene.materials[size_t(hs.material)];
            const Color passing = m.gltfPbr && m.seesThrough() ? gltfPassing(scene, hs, 0.f) : Color(0.f);
            if (passing != Color(0.f) && crossing < kGlassCrossings) {
                // Looked through, unbent: glass (and a blended surface's uncovered share) passes
                // the bounce on as its shadows pass light.
                g.through *= passing;
                skip = scene.geometry.skipFor(hs, dir);
                r.o = skip == hs.prim ? hs.p : offsetRayOrigin(hs.p, hs.pError, hs.ng, dir);
                continue;
            }
            const bool front = glm::dot(hs.ng, dir) < 0.f;
            if (!front) ++backFaces;
            g.p = hs.p;
            const Vec3 ng = front ? hs.ng : -hs.ng;
            g.n = front ? hs.ns : -hs.ns;
            if (glm::dot(g.n, -dir) <= 0.f) g.n = ng;
            hits.push_back(g);
            break;
        }
    }
    return hits;
}

}  // namespace

std::shared_ptr<const BounceGeometry> buildBounceGeometry(const Scene& scene, uint32_t count, int threads) {
    BouncePoints placed = placeBouncePoints(scene, count, threads);
    const size_t n = placed.points.size();
    if (n == 0) return nullptr;
    std::vector<std::vector<GatherHit>> hits(n);
    std::vector<uint8_t> outside(n, 0);
    std::vector<uint64_t> rays(n, 0);
    parallelFor(int(n), threads, [&](int i, int) {
        int back = 0;
        hits[size_t(i)] = gatherPoint(scene, placed.points[size_t(i)], uint32_t(i), back, rays[size_t(i)]);
        outside[size_t(i)] = !(float(back) > kInsideShare * float(kGatherRays));
    });
    uint64_t traced = placed.rays;
    for (uint64_t r : rays) traced += r;
    std::vector<std::vector<GatherHit>> kept;
    for (size_t i = 0; i < n; ++i)
        if (outside[i]) kept.push_back(std::move(hits[i]));
    placed.keep(outside);
    if (placed.points.empty()) return nullptr;
    auto geo = std::make_shared<BounceGeometry>();
    geo->rays = traced;
    geo->points = std::move(placed.points);
    geo->footprint = std::move(placed.footprint);
    geo->footprintStart = std::move(placed.footprintStart);
    // The kernel's radius: kPointsPerKernel points on a disc of it, at the density of the kept
    // ones, were they spread over one flat surface; then corrected by counting, since surfaces
    // packed close (an engine's parts) put many more within it.
    const double keptArea = placed.area * double(geo->points.size()) / double(n);
    float radius = float(std::sqrt(double(kPointsPerKernel) * keptArea / (kPi * double(geo->points.size()))));
    geo->grid = BounceGrid(geo->points, radius);
    for (int round = 0; round < 4; ++round) {
        const float m = geo->grid.meanNeighbours();
        if (!(m > 0.f) || (m > 0.7f * kPointsPerKernel && m < 1.5f * kPointsPerKernel)) break;
        radius *= std::clamp(std::sqrt(kPointsPerKernel / m), 0.25f, 2.f);
        geo->grid = BounceGrid(geo->points, radius);
    }

    // The transfer: each gather ray's landing spread over the points around it.
    geo->transfer.appendRows(geo->points.size(), threads, [&](size_t i, std::vector<std::pair<uint32_t, Color>>& row, KernelWeights& w) {
        for (const GatherHit& g : kept[i]) {
            geo->grid.weights(g.p, g.n, w, kLandingScale, kLandingMost);
            for (const auto& [j, wj] : w) row.emplace_back(j, g.through * (wj / float(kGatherRays)));
        }
        std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        size_t out = 0;
        for (size_t k = 0; k < row.size(); ++k) {
            if (out > 0 && row[out - 1].first == row[k].first) row[out - 1].second += row[k].second;
            else row[out++] = row[k];
        }
        row.resize(out);
    });
    geo->smooth.appendRows(geo->points.size(), threads, [&](size_t i, std::vector<std::pair<uint32_t, float>>& row, KernelWeights& w) {
        const BouncePoint& bp = geo->points[i];
        geo->grid.weights(bp.si.p, bp.frame.ns, w, 1.f, kSmoothMost);
        row.assign(w.begin(), w.end());
    });

    // Nodes: every vertex of a bounce mesh, per side, and grids over triangles wider than the
    // kernel (spacing grows if they would pass kMaxGridNodes).
    struct NodeSpec {
        Vec3 p, n;
    };
    std::vector<NodeSpec> nodes;
    geo->meshes.resize(scene.geometry.meshes.size());
    float spacing = radius;
    auto gridSide = [&](const TriangleMesh& mesh, uint32_t t) -> uint32_t {
        const Vec3& p0 = mesh.positions[mesh.indices[3 * t]];
        const Vec3& p1 = mesh.positions[mesh.indices[3 * t + 1]];
        const Vec3& p2 = mesh.positions[mesh.indices[3 * t + 2]];
        const float e = std::max({glm::length(p1 - p0), glm::length(p2 - p1), glm::length(p0 - p2)});
        if (!(e > spacing) || !std::isfinite(e)) return 1;
        return uint32_t(std::min(double(kMaxGridSide), std::ceil(double(e) / double(spacing))));
    };
    for (int pass = 0; pass < 8; ++pass) {
        size_t total = 0;
        for (size_t m = 0; m < scene.geometry.meshes.size(); ++m) {
            if (!bounceSurface(scene, int(m))) continue;
            for (uint32_t t = 0; t < scene.geometry.meshes[m].triangleCount(); ++t) {
                const size_t L = gridSide(scene.geometry.meshes[m], t);
                if (L > 1) total += (L + 1) * (L + 2) / 2;
            }
        }
        const size_t most = kGridNodesPerPoint * geo->points.size();
        if (total <= most) break;
        spacing *= float(std::sqrt(double(total) / double(most))) * 1.05f;
    }
    for (size_t m = 0; m < scene.geometry.meshes.size(); ++m) {
        const TriangleMesh& mesh = scene.geometry.meshes[m];
        if (!bounceSurface(scene, int(m))) continue;
        const bool both = scene.materials[size_t(mesh.material)].doubleSided;
        MeshNodes& mn = geo->meshes[m];
        // A mesh without normals (a scene file's) is shaded flat; its vertices take the
        // area-weighted mean of their faces' normals.
        std::vector<Vec3> faceMean;
        if (mesh.normals.empty()) {
            faceMean.assign(mesh.positions.size(), Vec3(0.f));
            for (size_t t = 0; t < mesh.triangleCount(); ++t) {
                const uint32_t* idx = &mesh.indices[3 * t];
                const Vec3 n = glm::cross(mesh.positions[idx[1]] - mesh.positions[idx[0]], mesh.positions[idx[2]] - mesh.positions[idx[0]]);
                for (int k = 0; k < 3; ++k) faceMean[idx[k]] += n;
            }
        }
        const std::vector<Vec3>& normals = mesh.normals.empty() ? faceMean : mesh.normals;
        for (int s = 0; s < (both ? 2 : 1); ++s) {
            const float side = s == 0 ? 1.f : -1.f;
            (s == 0 ? mn.front : mn.back) = int64_t(nodes.size());
            for (size_t v = 0; v < mesh.positions.size(); ++v) nodes.push_back({mesh.positions[v], side * normals[v]});
        }
        for (uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            const uint32_t L = gridSide(mesh, t);
            if (L <= 1) continue;
            if (mn.grid.empty()) mn.grid.assign(mesh.triangleCount(), ~0u);
            mn.grid[t] = uint32_t(geo->grids.size());
            TriGrid g;
            g.L = L;
            const uint32_t* idx = &mesh.indices[3 * t];
            for (int s = 0; s < (both ? 2 : 1); ++s) {
                const float side = s == 0 ? 1.f : -1.f;
                (s == 0 ? g.front : g.back) = int64_t(nodes.size());
                for (uint32_t a = 0; a <= L; ++a)
                    for (uint32_t b = 0; a + b <= L; ++b) {
                        const float b1 = float(a) / float(L), b2 = float(b) / float(L), b0 = 1.f - b1 - b2;
                        const Vec3 p = b0 * mesh.positions[idx[0]] + b1 * mesh.positions[idx[1]] + b2 * mesh.positions[idx[2]];
                        const Vec3 n = b0 * normals[idx[0]] + b1 * normals[idx[1]] + b2 * normals[idx[2]];
                        nodes.push_back({p, side * n});
                    }
            }
            geo->grids.push_back(g);
        }
    }
    geo->nodeWeights.appendRows(nodes.size(), threads, [&](size_t k, std::vector<std::pair<uint32_t, float>>& row, KernelWeights& w) {
        const float len = glm::length(nodes[k].n);
        if (!(len > 0.f) || !std::isfinite(len)) return;
        geo->grid.weights(nodes[k].p, nodes[k].n / len, w, kNodeScale, kNodeMost);
        row.assign(w.begin(), w.end());
    });
    return geo;
}

void BounceCache::light(const Scene& scene, int threads) {
    const BounceGeometry& g = *geometry_;
    const size_t n = g.points.size();
    std::vector<Color> direct(n);
    bool seeThrough = false;
    for (const Material& m : scene.materials) seeThrough |= m.gltfPbr && m.seesThrough();
    // The radiance leaving one place on a surface: emission and the diffuse reflection of the
    // lights that reach it.
    auto leavingAt = [&](const BouncePoint& bp, RayStats& stats, ShadowBlockers& blockers) {
        Color e(0.f);
        if (bp.albedo != Color(0.f)) {
            ShadowRays shadows(scene, bp.si, bp.frame, &blockers);
            for (const Light& L : scene.lights) {
                LightIncidence li;
                if (!lightIncidence(L, bp.si.p, bp.frame.ns, li)) continue;
                if (glm::dot(bp.frame.ng, li.dir) <= 0.f) continue;
                Color term = li.att * li.cosine * L.intensity * L.color;
                if (L.castShadows) term *= shadows.transmittance(L, li, false, stats, seeThrough);
                e += term;
            }
        }
        return bp.emission + bp.albedo * (1.f / kPi) * e;
    };
    const int chunks = int((n + 255) / 256);
    std::vector<uint64_t> chunkRays(size_t(chunks), 0);
    parallelFor(chunks, threads, [&](int c, int) {
        RayStats stats;
        // Footprint places of one point lie close together: the blocker of one is the likely
        // blocker of the next (it changes what the shadow rays cost, never what they answer).
        ShadowBlockers blockers(scene.lights.size());
        for (size_t i = size_t(c) * 256; i < std::min(n, size_t(c + 1) * 256); ++i) {
            Color sum(0.f);
            for (uint32_t k = g.footprintStart[i]; k < g.footprintStart[i + 1]; ++k) sum += leavingAt(g.footprint[k], stats, blockers);
            direct[i] = sum / float(g.footprintStart[i + 1] - g.footprintStart[i]);
        }
        chunkRays[size_t(c)] = stats.total();
    });
    rays_ = 0;
    for (uint64_t r : chunkRays) rays_ += r;
    // What leaves a point is read as the mean over its kernel: a point stands for the surface
    // around it, and a shadow smaller than the points' spacing must dim it by its share, not
    // switch it off or on as the light turns (that would make a turntable flicker).
    std::vector<Color> leaving, gathered;
    g.smooth.apply(direct, leaving, threads);
    direct = leaving;
    // Bounce k arrives as transfer × (what left the points after k − 1 bounces).
    for (int k = 0; k < kBounces; ++k) {
        g.transfer.apply(leaving, gathered, threads);
        g.smooth.apply(gathered, pointBounce_, threads);
        if (k + 1 < kBounces)
            for (size_t i = 0; i < n; ++i) leaving[i] = direct[i] + g.points[i].albedo * pointBounce_[i];
    }
    g.nodeWeights.apply(pointBounce_, nodeBounce_, threads);
}

Color BounceCache::at(const Scene& scene, const SurfaceInteraction& si, float side) const {
    const BounceGeometry& g = *geometry_;
    if (si.mesh < 0 || size_t(si.mesh) >= g.meshes.size()) return Color(0.f);
    const MeshNodes& mn = g.meshes[size_t(si.mesh)];
    const float b0 = si.bary.b0, b1 = si.bary.b1, b2 = si.bary.b2;
    if (!mn.grid.empty() && mn.grid[si.tri] != ~0u) {
        const TriGrid& tg = g.grids[mn.grid[si.tri]];
        const int64_t base = side > 0.f ? tg.front : tg.back;
        if (base < 0) return Color(0.f);
        const float L = float(tg.L);
        const float u = std::clamp(b1, 0.f, 1.f) * L, v = std::clamp(b2, 0.f, 1.f) * L;
        uint32_t a = std::min(uint32_t(u), tg.L - 1);
        uint32_t b = std::min(uint32_t(v), tg.L - 1 - a);
        const float fu = u - float(a), fv = v - float(b);
        const Color* node = nodeBounce_.data() + base;
        if (fu + fv <= 1.f || a + b + 1 >= tg.L)
            return (1.f - fu - fv) * node[gridIndex(tg.L, a, b)] + fu * node[gridIndex(tg.L, a + 1, b)] +
                   fv * node[gridIndex(tg.L, a, b + 1)];
        return (fu + fv - 1.f) * node[gridIndex(tg.L, a + 1, b + 1)] + (1.f - fv) * node[gridIndex(tg.L, a + 1, b)] +
               (1.f - fu) * node[gridIndex(tg.L, a, b + 1)];
    }
    const int64_t base = side > 0.f ? mn.front : mn.back;
    if (base < 0) return Color(0.f);
    const uint32_t* idx = &scene.geometry.meshes[size_t(si.mesh)].indices[3 * size_t(si.tri)];
    const Color* node = nodeBounce_.data() + base;
    return b0 * node[idx[0]] + b1 * node[idx[1]] + b2 * node[idx[2]];
}

namespace {
bool geometryMoves(const Scene& scene) {
    for (const TriangleMesh& m : scene.geometry.meshes)
        if (m.node >= 0) return true;
    return false;
}
}  // namespace

bool bounceApplies(const Scene& scene) {
    bool surface = false, glowing = false;
    for (size_t m = 0; m < scene.geometry.meshes.size() && !surface; ++m) surface = bounceSurface(scene, int(m));
    for (const Material& mat : scene.materials) glowing |= mat.gltfPbr && mat.emission != Color(0.f);
    return surface && (!scene.lights.empty() || glowing);
}

bool bounceLeftOutForMotion(const Scene& scene, const RenderSettings& settings) {
    return settings.bounce > 0 && settings.indirectSamples == 0 && !settings.bounceMoving && !scene.lights.empty() &&
           geometryMoves(scene);
}

std::shared_ptr<const BounceCache> bounceCache(const Scene& scene, const RenderSettings& settings,
                                               SceneCacheSlot* slotIn, int threads, RayStats* spent) {
    if (settings.bounce <= 0 || settings.indirectSamples > 0 || !slotIn) return nullptr;
    if (!settings.bounceMoving && geometryMoves(scene)) return nullptr;
    const uint32_t points = bouncePoints(settings);
    const uint64_t lights = lightsKey(scene);
    std::lock_guard<std::mutex> lock(slotIn->mutex);
    if (!slotIn->state) slotIn->state = std::make_shared<BounceSlot>();
    BounceSlot& slot = *std::static_pointer_cast<BounceSlot>(slotIn->state);
    const uint64_t materials = materialsKey(scene);
    const bool sameGeometry = slot.geometryVersion == scene.geometry.version() && slot.points == points && slot.materials == materials;
    if (sameGeometry)
        for (size_t i = 0; i < slot.lit.size(); ++i)
            if (slot.lit[i].first == lights) {
                std::rotate(slot.lit.begin(), slot.lit.begin() + std::ptrdiff_t(i), slot.lit.begin() + std::ptrdiff_t(i) + 1);
                return slot.lit.front().second;
            }
    const bool lit = !scene.lights.empty();
    if (!sameGeometry || (!slot.geometry && lit && !slot.triedLit)) {
        // Without lights only emission can bounce; without either there is nothing to build.
        slot.geometry = bounceApplies(scene) ? buildBounceGeometry(scene, points, threads) : nullptr;
        if (spent && slot.geometry) spent->bounce += slot.geometry->rays;
        slot.geometryVersion = scene.geometry.version();
        slot.materials = materials;
        slot.points = points;
        slot.triedLit = lit;
        slot.lit.clear();
    }
    if (!slot.geometry) return nullptr;
    auto cache = std::make_shared<BounceCache>(slot.geometry);
    cache->light(scene, threads);
    if (spent) spent->bounce += cache->rays();
    slot.lit.insert(slot.lit.begin(), {lights, cache});
    if (slot.lit.size() > BounceSlot::kLitKept) slot.lit.pop_back();
    return cache;
}

}  // namespace rf
