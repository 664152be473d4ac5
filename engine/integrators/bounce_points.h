#pragma once
/// The surface points of the bounce cache (bounce_cache.h) and the kernel that spreads what they
/// know over the surfaces between them. Points sit on the glTF surfaces at an even density
/// chosen from their area, one side each (both for double-sided materials), and a hash grid
/// finds those near a position. Everything here is a function of the geometry alone, built in
/// a fixed order, so every rank and thread count gets the same points and weights.
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/geometry/interaction.h"
#include "engine/integrators/shading_frame.h"

namespace rf {

class Scene;

/// One point of the cache: where it is, which side of the surface it stands for, and what that
/// surface does with light arriving there.
struct BouncePoint {
    SurfaceInteraction si;
    ShadingFrame frame;     ///< oriented to the point's side
    Color albedo{0.f};      ///< diffuse albedo: base colour × (1 − metallic) × (1 − transmission)
    Color emission{0.f};
};

/// (index, weight) pairs of a kernel query; the weights sum to 1 when there are any.
using KernelWeights = std::vector<std::pair<uint32_t, float>>;

/// Points binned in a uniform grid of cells one kernel radius wide.
class BounceGrid {
public:
    BounceGrid() = default;
    BounceGrid(const std::vector<BouncePoint>& points, float radius);

    /// The normalised kernel weights of the points near p whose side faces along n: a smooth
    /// bump in distance (zero at the radius), times agreement of normals, times nearness to the
    /// point's tangent plane (so parallel surfaces closer than the radius do not bleed into
    /// each other). Where nothing answers within the radius, twice and then four times the
    /// radius are tried; then none. scale: of the radius (at most 1). most: the strongest this
    /// many are kept (a vertex needs no more to be smooth once the points' own values are).
    void weights(const Vec3& p, const Vec3& n, KernelWeights& out, float scale = 1.f, size_t most = SIZE_MAX) const;
    float radius() const { return radius_; }
    /// The mean number of points within the radius of a sample of the points (normals aside).
    float meanNeighbours() const;

private:
    /// Adds the weights of the points within r of p; returns their sum.
    float gather(const Vec3& p, const Vec3& n, float r, KernelWeights& out) const;
    /// Calls visit(index) for every point in the cells the ball of radius r about p overlaps,
    /// in a fixed order (cell by cell, then by index).
    template <class Visit>
    void forEachNear(const Vec3& p, float r, Visit&& visit) const;
    uint64_t key(int x, int y, int z) const;

    const std::vector<BouncePoint>* points_ = nullptr;
    float radius_ = 1.f;
    float inv_ = 1.f;
    Vec3 origin_{0.f};
    std::vector<uint32_t> order_;  ///< point indices sorted by cell, then by index
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> cells_;  ///< cell -> range in order_
    /// The dense table, when the bounds hold at most kMaxDenseCells cells: cell c's points are
    /// order_[denseStart_[c], denseStart_[c + 1]); empty otherwise (cells_ then).
    static constexpr size_t kMaxDenseCells = size_t(1) << 21;
    glm::ivec3 dims_{0};
    std::vector<uint32_t> denseStart_;
    size_t dense(int x, int y, int z) const { return (size_t(z) * size_t(dims_.y) + size_t(y)) * size_t(dims_.x) + size_t(x); }
};

/// Whether a mesh's material takes part in the bounce: glTF, lit (not unlit), not wholly
/// transmissive (glass is looked through, never lit by the cache).
bool bounceSurface(const Scene& scene, int mesh);

/// The cache's points, and for each the places on its surface around it where its direct light
/// is measured (its footprint: the point itself first, then up to kFootprint − 1 more on a disc
/// as large as the point's share of the area, those that fall inside its triangle). A shadow
/// smaller than the spacing then dims a point by about its share, instead of switching it off
/// or on as the light turns.
struct BouncePoints {
    static constexpr uint32_t kFootprint = 16;
    std::vector<BouncePoint> points;
    std::vector<BouncePoint> footprint;
    std::vector<uint32_t> footprintStart{0};  ///< point i's footprint: [start[i], start[i + 1])
    double area = 0.0;  ///< the bounce surfaces' area, sides counted
    uint64_t rays = 0;  ///< rays cast to place the points and their footprints

    /// Keeps the points (and their footprints) whose keep[i] is set, in order.
    void keep(const std::vector<uint8_t>& keep);
};

/// About `count` points spread over the bounce surfaces by area (each side of a double-sided
/// material counted; each mesh side at least a few), at stratified positions along the area's
/// running sum; each is placed by a ray cast onto its surface so it carries the interaction
/// shading would see there.
BouncePoints placeBouncePoints(const Scene& scene, uint32_t count, int threads);

}  // namespace rf
