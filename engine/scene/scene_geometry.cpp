// Every ray query of the scene's geometry, in the order a ray meets them: intersect (or a
// camera packet's intersectPacket) and occluded, each walking the top level and the instances'
// trees (walk) down to a leaf's slots (intersectLeaf, intersectSlot); then what a hit is
// (interaction) and what a ray spawned there must skip (skipFor).
#include "engine/scene/scene_geometry.h"

#include <algorithm>
#include <cstring>
#include <new>

#include "engine/geometry/prim_bounds.h"
#include "engine/materials/material_eval.h"

namespace rf {

// One function on purpose, though past 60 lines: it is every ray's first call, and the order it
// tries things in (the inside-sphere exit, planes to bound tMax, then the BVH or the flat lists)
// is the whole point of it; split, that order would hide across files.
bool SceneGeometry::intersect(const Ray& r, Hit& hit, uint32_t skip) const {
    float tMax = r.tMax;
    bool found = false;
    const uint32_t nTri = nTri_, base = nTri_ + nSph_;
    const uint32_t inside = insidePrim(skip);
    const bool fromInside = inside >= nTri && inside < base;
    if (fromInside && sphereAlone_[inside - nTri]) {
        // Nothing else reaches into the sphere the ray starts in: its exit is the next hit.
        float t;
        Vec3 rel;
        if (!intersectSphereFromInside(spheres[inside - nTri], r, tMax, t, &rel)) return false;
        hit.t = t;
        hit.prim = inside;
        hit.sphereRel = rel;
        return true;
    }
    // Planes first: their hit bounds tMax cheaply for the sphere pre-test.
    for (size_t i = 0; i < planes.size(); ++i) {
        float t;
        const uint32_t id = base + static_cast<uint32_t>(i);
        if (id != skip && intersectPlane(planes[i], r, 0.f, tMax, t)) {
            tMax = t;
            hit.t = t;
            hit.prim = id;
            found = true;
        }
    }
    if (useBvh_) {
        // The triangle test's set-up waits for the first leaf: most rays that miss the model
        // never reach one.
        bool wrReady = false;
        WatertightRay wr;
        const SceneInstance* wrFor = nullptr;  // whose space wr is in (rays of untransformed instances share r's)
        found |= walk(r, tMax, false, [&](const SceneInstance& in, const Ray& ri, uint32_t first, uint32_t count, float& tm) {
            const SceneInstance* space = in.transformed ? &in : nullptr;
            if (wrFor != space || !wrReady) wr = WatertightRay(ri), wrFor = space, wrReady = true;
            return intersectLeaf(in, first, count, ri, wr, tm, hit, skip, false);
        });
    } else {
        const WatertightRay wr = nTri ? WatertightRay(r) : WatertightRay();
        for (uint32_t p = 0; p < nTri; ++p) found |= intersectSlot(p, r, wr, tMax, hit, skip);
        uint32_t m = spheres.empty() ? 0 : sphereCandidates(r, tMax);
        if (skip >= nTri && skip < base) m &= ~(1u << (skip - nTri));
        if (fromInside) {
            // The sphere the ray starts in: its exit bounds everything else.
            m &= ~(1u << (inside - nTri));
            float t;
            Vec3 rel;
            if (intersectSphereFromInside(spheres[inside - nTri], r, tMax, t, &rel)) {
                tMax = t;
                hit.t = t;
                hit.prim = inside;
                hit.sphereRel = rel;
                found = true;
            }
        }
        for (; m; m &= m - 1) {
            const uint32_t i = static_cast<uint32_t>(__builtin_ctz(m));
            float t;
            Vec3 rel;
            if (!intersectSphereExact(spheres[i], r, 0.f, tMax, t, &rel)) continue;
            tMax = t;
            hit.t = t;
            hit.prim = nTri + i;
            hit.sphereRel = rel;
            found = true;
        }
    }
    return found;
}

void SceneGeometry::intersectPacket(const Ray* rays, int n, Hit* hits, bool* met) const {
    // Over several instances the packet walks each tree in turn, with no top level to cull
    // them: worth it for a few (a static set and a character), not for many animated parts.
    if (!useBvh_ || n > Bvh::kPacketMax || instances_.size() > kPacketInstances) {
        for (int i = 0; i < n; ++i) met[i] = intersect(rays[i], hits[i]);
        return;
    }
    const uint32_t base = nTri_ + nSph_;
    float tMax[Bvh::kPacketMax];
    alignas(WatertightRay) unsigned char storage[sizeof(WatertightRay) * Bvh::kPacketMax];
    WatertightRay* wr = reinterpret_cast<WatertightRay*>(storage);  // the packet's n, no more
    for (int i = 0; i < n; ++i) {
        const Ray& r = rays[i];
        tMax[i] = r.tMax;
        met[i] = false;
        // Planes first, as intersect() takes them.
        for (size_t k = 0; k < planes.size(); ++k) {
            float t;
            if (intersectPlane(planes[k], r, 0.f, tMax[i], t)) {
                tMax[i] = t;
                hits[i].t = t;
                hits[i].prim = base + static_cast<uint32_t>(k);
                met[i] = true;
            }
        }
        new (wr + i) WatertightRay(r);
    }
    for (const SceneInstance& in : instances_) {
        if (in.hidden) continue;
        if (!in.transformed) {
            in.bvh.traversePacket(rays, n, tMax, [&](int i, uint32_t first, uint32_t count, float& tm) {
                const bool hit = intersectLeaf(in, first, count, rays[i], wr[i], tm, hits[i], kNoPrim, false);
                met[i] |= hit;
                return hit;
            });
            continue;
        }
        // One origin in, one origin out: every ray's is transformed by the same operations.
        Ray ro[Bvh::kPacketMax];
        alignas(WatertightRay) unsigned char objStorage[sizeof(WatertightRay) * Bvh::kPacketMax];
        WatertightRay* wo = reinterpret_cast<WatertightRay*>(objStorage);
        for (int i = 0; i < n; ++i) {
            ro[i] = in.toObject(rays[i]);
            new (wo + i) WatertightRay(ro[i]);
        }
        in.bvh.traversePacket(ro, n, tMax, [&](int i, uint32_t first, uint32_t count, float& tm) {
            const bool hit = intersectLeaf(in, first, count, ro[i], wo[i], tm, hits[i], kNoPrim, false);
            met[i] |= hit;
            return hit;
        });
    }
}

bool SceneGeometry::occluded(const Ray& r, float tMax, uint32_t skip, uint32_t* lastBlocker) const {
    const uint32_t nTri = nTri_, base = nTri_ + nSph_;
    // Any hit will do: a ray that leaves the sphere it starts in before tMax is blocked by it.
    const uint32_t inside = insidePrim(skip);
    const bool fromInside = inside >= nTri && inside < base;
    if (fromInside) {
        float t;
        if (intersectSphereFromInside(spheres[inside - nTri], r, tMax, t)) return true;
    }
    for (size_t i = 0; i < planes.size(); ++i)
        if (base + i != skip && planeBlocks(planes[i], r, tMax)) return true;
    const WatertightRay wr = nTri ? WatertightRay(r) : WatertightRay();
    Hit scratch;
    if (useBvh_) {
        // The guess only for triangles of render-space trees: a rigid instance's walk tests
        // object-space copies, which the render-space triangle need not match bit for bit.
        if (lastBlocker && *lastBlocker < nTri && *lastBlocker != skip && !instances_[primInstance_[*lastBlocker]].transformed &&
            walkWouldBlock(*lastBlocker, r, wr, tMax))
            return true;
        WatertightRay wo;
        const SceneInstance* woFor = nullptr;
        const bool blocked = walk(r, tMax, true, [&](const SceneInstance& in, const Ray& ri, uint32_t first, uint32_t count, float& tm) {
            if (!in.transformed) return intersectLeaf(in, first, count, r, wr, tm, scratch, skip, true);
            if (woFor != &in) wo = WatertightRay(ri), woFor = &in;
            return intersectLeaf(in, first, count, ri, wo, tm, scratch, skip, true);
        });
        // A lit point forgets the blocker: its neighbours are likely lit too, and need no guess.
        if (lastBlocker) *lastBlocker = blocked ? scratch.prim : kNoPrim;
        return blocked;
    }
    float tm = tMax;
    for (uint32_t p = 0; p < nTri; ++p)
        if (intersectSlot(p, r, wr, tm, scratch, skip)) return true;
    uint32_t sure = 0;
    uint32_t m = spheres.empty() ? 0 : sphereCandidates(r, tMax, &sure);
    if (skip >= nTri && skip < base) {
        m &= ~(1u << (skip - nTri));
        sure &= ~(1u << (skip - nTri));
    }
    if (fromInside) {  // tested first, above
        m &= ~(1u << (inside - nTri));
        sure &= ~(1u << (inside - nTri));
    }
    if (sure) return true;
    for (; m; m &= m - 1) {
        float t;
        if (intersectSphereExact(spheres[__builtin_ctz(m)], r, 0.f, tMax, t)) return true;
    }
    return false;
}

uint32_t SceneGeometry::skipFor(const SurfaceInteraction& si, const Vec3& dir) const {
    const uint32_t nTri = nTri_, base = nTri_ + nSph_;
    if (si.prim >= base && si.prim < base + planes.size()) return si.prim;
    // si.ng of a sphere is its outward normal: a ray leaving outwards cannot come back, one
    // heading in meets it once more, at its exit.
    if (si.prim >= nTri && si.prim < base) {
        const float dn = glm::dot(dir, si.ng);
        if (dn > 0.f) return si.prim;
        if (dn < 0.f) return si.prim | kFromInside;
    }
    return kNoPrim;
}

namespace {
/// The texture-coordinate area a cone of width w covers where it meets a triangle with world
/// edge cross product length len and texture coordinates t0, t1, t2 at incidence cosine
/// `cosine`: the footprint's area on the surface (w²/|cos|, capped at grazing), times the
/// triangle's ratio of texture area to world area.
float uvFootprint(float w, float cosine, float len, Vec2 t0, Vec2 t1, Vec2 t2) {
    const Vec2 a = t1 - t0, b = t2 - t0;
    const float uvLen = std::abs(a.x * b.y - a.y * b.x);
    return w * w / std::max(std::abs(cosine), 1e-2f) * (uvLen / len);
}
}  // namespace

SurfaceInteraction SceneGeometry::interaction(const Ray& r, const Hit& hit) const {
    SurfaceInteraction si;
    si.prim = hit.prim;
    si.coneWidth = r.coneWidth + r.coneSpread * hit.t;
    si.coneSpread = r.coneSpread;
    const uint32_t nTri = nTri_, nSph = nSph_;
    if (hit.prim < nTri) {
        const Vec3& p0 = triVerts_[3 * hit.prim];
        const Vec3& p1 = triVerts_[3 * hit.prim + 1];
        const Vec3& p2 = triVerts_[3 * hit.prim + 2];
        si.p = triangleHitPoint(p0, p1, p2, hit.tri, si.pError);
        // A rigid instance's hit was found on its object-space triangle with the ray taken
        // there; the render-space triangle is that one moved and rounded. Rays spawned here go
        // back through the same transform: the offset also covers both roundings (a few ulps of
        // the point).
        if (useBvh_ && instances_[primInstance_[hit.prim]].transformed) si.pError += gamma(4) * absComponents(si.p);
        const Vec3 n = glm::cross(p1 - p0, p2 - p0);
        const float len = glm::length(n);
        si.ng = len > 0.f ? n / len : -r.d;
        const TriangleMesh& mesh = meshes[triMesh_[hit.prim]];
        const uint32_t* idx = &mesh.indices[3 * triLocal_[hit.prim]];
        const float b0 = hit.tri.b0, b1 = hit.tri.b1, b2 = hit.tri.b2;
        // A mirroring pose turned the file's front faces clockwise (mesh.h): the facet normal
        // turns with them, so that it points out of the surface the file meant.
        if (mesh.mirrored || (!mesh.mirroredVertices.empty() &&
                              mesh.mirroredVertices[idx[0]] + mesh.mirroredVertices[idx[1]] + mesh.mirroredVertices[idx[2]] >= 2))
            si.ng = -si.ng;
        si.ns = si.ng;
        if (!mesh.normals.empty()) {
            const Vec3 ns = b0 * mesh.normals[idx[0]] + b1 * mesh.normals[idx[1]] + b2 * mesh.normals[idx[2]];
            const float nl = glm::length(ns);
            // Zero or non-finite interpolated normals (cone apex, bad data) fall back on ng.
            if (nl > 1e-12f && std::isfinite(nl)) si.ns = ns / nl;
        }
        if (!mesh.uvs.empty()) si.uv = b0 * mesh.uvs[idx[0]] + b1 * mesh.uvs[idx[1]] + b2 * mesh.uvs[idx[2]];
        if (!mesh.uvs1.empty()) si.uv1 = b0 * mesh.uvs1[idx[0]] + b1 * mesh.uvs1[idx[1]] + b2 * mesh.uvs1[idx[2]];
        if (!mesh.tangents.empty())
            si.tangent = b0 * mesh.tangents[idx[0]] + b1 * mesh.tangents[idx[1]] + b2 * mesh.tangents[idx[2]];
        if (!mesh.colors.empty()) si.color = b0 * mesh.colors[idx[0]] + b1 * mesh.colors[idx[1]] + b2 * mesh.colors[idx[2]];
        if (si.coneWidth > 0.f && len > 0.f) {
            const float cosine = glm::dot(si.ng, r.d);
            if (!mesh.uvs.empty())
                si.uvArea.x = uvFootprint(si.coneWidth, cosine, len, mesh.uvs[idx[0]], mesh.uvs[idx[1]], mesh.uvs[idx[2]]);
            if (!mesh.uvs1.empty())
                si.uvArea.y = uvFootprint(si.coneWidth, cosine, len, mesh.uvs1[idx[0]], mesh.uvs1[idx[1]], mesh.uvs1[idx[2]]);
        }
        si.material = mesh.material;
        si.mesh = static_cast<int>(triMesh_[hit.prim]);
        si.tri = triLocal_[hit.prim];
        si.bary = hit.tri;
    } else if (hit.prim < nTri + nSph) {
        const Sphere& s = spheres[hit.prim - nTri];
        si.p = s.center + hit.sphereRel;
        si.pError = gamma(5) * absComponents(hit.sphereRel) + gamma(2) * absComponents(si.p);
        si.ng = si.ns = hit.sphereRel * (1.f / s.radius);
        si.material = s.material;
    } else {
        const Plane& pl = planes[hit.prim - nTri - nSph];
        si.p = planeHitPoint(pl, r, hit.t, si.pError);
        si.ng = si.ns = pl.n;
        si.material = pl.material;
    }
    return si;
}

Aabb SceneGeometry::bounds() const {
    Aabb b;
    for (const Sphere& s : spheres) b.grow(sphereBox(s));
    for (const TriangleMesh& m : meshes)
        for (const Vec3& p : m.positions) b.grow(p);
    return b;
}

template <typename LeafFn>
bool SceneGeometry::walk(const Ray& r, float tMax, bool anyHit, LeafFn&& leaf) const {
    if (!twoLevel_) {
        const SceneInstance& in = instances_[0];
        return in.bvh.traverseLeaves(r, tMax, anyHit, [&](uint32_t first, uint32_t count, float& tm) {
            return leaf(in, r, first, count, tm);
        });
    }
    const std::vector<uint32_t>& order = top_.primIndex();
    return top_.traverseLeaves(r, tMax, anyHit, [&](uint32_t first, uint32_t count, float& tm) {
        bool hit = false;
        for (uint32_t k = first; k < first + count; ++k) {
            const SceneInstance& in = instances_[topInstance_[order[k]]];
            const Ray ri = in.transformed ? in.toObject(r) : r;
            // The instance's walk keeps its own limit; a hit lowers the top level's too.
            const bool h = in.bvh.traverseLeaves(ri, tm, anyHit, [&](uint32_t a, uint32_t n, float& tIn) {
                const bool got = leaf(in, ri, a, n, tIn);
                if (got) tm = tIn;
                return got;
            });
            if (h) {
                hit = true;
                if (anyHit) return true;
            }
        }
        return hit;
    });
}

bool SceneGeometry::intersectLeaf(const SceneInstance& in, uint32_t first, uint32_t count, const Ray& r, const WatertightRay& wr,
                          float& tMax, Hit& hit, uint32_t skip, bool anyHit) const {
    bool found = false;
    uint32_t b = in.leafTris.firstBlock(first);
    first += in.slotBase;
    if (b == LeafTriangles::kNone) {
        for (uint32_t s = first; s < first + count; ++s)
            if (slotPrim_[s] != skip && intersectSlot(s, r, wr, tMax, hit, skip)) {
                found = true;
                if (anyHit) return true;
            }
        return found;
    }
    // Triangles only: the four-wide pre-test rules most of them out; the rest go through the
    // scalar test in slot order, as above.
    for (uint32_t s = first; s < first + count; s += 4, ++b) {
        uint32_t m = watertightCandidates4(wr, in.leafTris.block(b));
        if (first + count - s < 4) m &= (1u << (first + count - s)) - 1u;
        for (; m; m &= m - 1) {
            const uint32_t slot = s + static_cast<uint32_t>(__builtin_ctz(m));
            if (slotPrim_[slot] != skip && intersectSlot(slot, r, wr, tMax, hit, skip)) {
                found = true;
                if (anyHit) return true;
            }
        }
    }
    return found;
}

bool SceneGeometry::triangleAlphaPasses(uint32_t tri, const TriangleHit& h) const {
    const TriangleMesh& mesh = meshes[triMesh_[tri]];
    const Material& mat = maskMaterials_[mesh.material];
    // The same lookup as shading (material_eval.h): the texCoord set and KHR_texture_transform
    // the material names, so the cut-out traversal sees is the one the picture shows.
    Vec2 uv0(0.f), uv1(0.f);
    const uint32_t* idx = &mesh.indices[3 * triLocal_[tri]];
    if (!mesh.uvs.empty()) uv0 = h.b0 * mesh.uvs[idx[0]] + h.b1 * mesh.uvs[idx[1]] + h.b2 * mesh.uvs[idx[2]];
    if (!mesh.uvs1.empty()) uv1 = h.b0 * mesh.uvs1[idx[0]] + h.b1 * mesh.uvs1[idx[1]] + h.b2 * mesh.uvs1[idx[2]];
    float alpha = materialAlpha(maskTextures_, mat, uv0, uv1);
    if (!mesh.colors.empty()) alpha *= h.b0 * mesh.colors[idx[0]].a + h.b1 * mesh.colors[idx[1]].a + h.b2 * mesh.colors[idx[2]].a;
    return alpha >= mat.alphaCutoff;
}

bool SceneGeometry::intersectSlot(uint32_t slot, const Ray& r, const WatertightRay& wr, float& tMax, Hit& hit, uint32_t skip) const {
    const uint32_t prim = slotPrim_[slot];
    if (prim < nTri_) {
        TriangleHit th;
        const Vec3* v = &slotVerts_[3 * slot];
        if (!intersectTriangleWatertight(wr, v[0], v[1], v[2], tMax, th)) return false;
        if (anyMasked_ && meshMasked_[triMesh_[prim]] && !triangleAlphaPasses(prim, th)) return false;
        tMax = th.t;
        hit.t = th.t;
        hit.prim = prim;
        hit.tri = th;
        return true;
    }
    float t;
    Vec3 rel;
    const Sphere& s = spheres[prim - nTri_];
    if (!(prim == insidePrim(skip) ? intersectSphereFromInside(s, r, tMax, t, &rel) : intersectSphere(s, r, 0.f, tMax, t, &rel)))
        return false;
    tMax = t;
    hit.t = t;
    hit.prim = prim;
    hit.sphereRel = rel;
    return true;
}

bool SceneGeometry::walkWouldBlock(uint32_t prim, const Ray& r, const WatertightRay& wr, float tMax) const {
    TriangleHit th;
    const Vec3* v = &triVerts_[3 * prim];  // the same floats as the prim's slot in slotVerts_
    if (!intersectTriangleWatertight(wr, v[0], v[1], v[2], tMax, th)) return false;
    if (anyMasked_ && meshMasked_[triMesh_[prim]] && !triangleAlphaPasses(prim, th)) return false;
    // A hit within an ulp of tMax can lie past the entry distance the walk's box test computes;
    // the walk then lets the ray through, and so must the guess.
    return Bvh::boxPasses(RayBoxPrecomp(r), triangleBox(v[0], v[1], v[2]), tMax);
}

uint32_t SceneGeometry::sphereCandidates(const Ray& r, float tMax, uint32_t* sure) const {
    // The float test of sphereMayHit for all lanes at once, without branches or divisions
    // (a·v = a·f − b·d). GCC/Clang vector extensions: SSE2 on any x86-64, NEON elsewhere.
    static_assert(kBvhThreshold == 8, "two lanes of four");
    const float a = glm::dot(r.d, r.d);
    const float oErr = 32.f * kMachineEps * maxComponent(absComponents(r.o));
    const F4 ox = {r.o.x, r.o.x, r.o.x, r.o.x}, oy = {r.o.y, r.o.y, r.o.y, r.o.y}, oz = {r.o.z, r.o.z, r.o.z, r.o.z};
    const F4 dx = {r.d.x, r.d.x, r.d.x, r.d.x}, dy = {r.d.y, r.d.y, r.d.y, r.d.y}, dz = {r.d.z, r.d.z, r.d.z, r.d.z};
    const F4 av = {a, a, a, a}, errv = {oErr, oErr, oErr, oErr}, zero = {0.f, 0.f, 0.f, 0.f};
    constexpr float kSlack = 16.f * kMachineEps;
    const F4 slack = {kSlack, kSlack, kSlack, kSlack};
    // Entry no earlier than (|f| − reach)/|d|: |f| > reach + tMax·|d| cannot hit before tMax.
    // |d| ≤ (a + 1)/2 (AM–GM; equal for a unit direction): a bound without a square root.
    const float far = tMax * (0.5f * (a + 1.f)) * (1.f + 1e-5f);
    const F4 farv = {far, far, far, far};
    // Sure hit: outside, approaching, the line well inside the sphere, and the closest approach
    // (after the entry) before tMax, all with margins far above the float error.
    const float aT = a * tMax * (1.f - 1e-4f);
    const F4 aTv = {aT, aT, aT, aT}, grow = {1.f + 1e-4f, 1.f + 1e-4f, 1.f + 1e-4f, 1.f + 1e-4f};
    uint32_t mask = 0, sureMask = 0;
    // Only the groups of four that hold spheres (a typical Whitted scene fills one).
    const int groups = static_cast<int>((nSph_ + 3) / 4);
    for (int h = 0; h < groups; ++h) {
        F4 cx, cy, cz, rr, ri;
        std::memcpy(&cx, sphX_ + 4 * h, sizeof cx);
        std::memcpy(&cy, sphY_ + 4 * h, sizeof cy);
        std::memcpy(&cz, sphZ_ + 4 * h, sizeof cz);
        std::memcpy(&rr, sphReach_ + 4 * h, sizeof rr);
        std::memcpy(&ri, sphInner_ + 4 * h, sizeof ri);
        const F4 fx = ox - cx, fy = oy - cy, fz = oz - cz;
        const F4 b = fx * dx + fy * dy + fz * dz;
        const F4 reach = rr + errv;
        const F4 reach2 = reach * reach;
        const F4 f2 = fx * fx + fy * fy + fz * fz;
        // The closest approach: a·|v|² = a·|f|² − b² (v = f − (b/a)·d), from b and |f|² computed
        // side by side, a shorter dependent chain than forming v. Both terms are ≤ a·|f|²
        // (Cauchy–Schwarz), so their rounding stays below 8 ulps of a·|f|²: a slack of 16 ulps
        // covers it and only lets more candidates through, never fewer.
        const F4 av2 = av * f2 - b * b;
        const F4 slackA = av * slack * f2;
        const I4 beside = av2 > av * reach2 + slackA;
        const F4 farReach = reach + farv;
        const I4 away = ((f2 > reach2) & (b > zero)) | (f2 > farReach * farReach);
        const I4 pass = ~(beside | away) & (reach > zero);
        mask |= laneMask(pass) << (4 * h);
        if (sure) {
            const F4 inner = ri - errv;
            const I4 through = (inner > zero) & ((av2 + slackA) * grow < av * inner * inner);
            const I4 ahead = (b < zero) & (f2 > reach2 * grow) & (-b * grow < aTv);
            sureMask |= laneMask(pass & through & ahead) << (4 * h);
        }
    }
    if (sure) *sure = sureMask;
    return mask;
}

}  // namespace rf
