// The scene's two-level acceleration structure (scene_instance.h): which primitives go into
// which instance, each instance's tree and slots, rigid instances moved by their node's matrix,
// and the top level over them.
#include <map>
#include <tuple>

#include "engine/geometry/prim_bounds.h"
#include "engine/scene/scene.h"

namespace rf {

namespace {

/// Whether a moving mesh is moved whole by its node's matrix (its object-space tree kept for
/// the film) rather than vertex by vertex (skin, morph targets).
bool rigidMesh(const TriangleMesh& m) {
    return m.skin < 0 && m.morphPositions.empty() && m.objectPositions.size() == m.positions.size();
}

/// The box b (object space) moved by m, in double, then widened outwards by a few float steps
/// so that the float box holds every point of the exact one.
Aabb transformedBox(const Aabb& b, const DMat4& m) {
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 p((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z);
        const glm::dvec3 q(m * glm::dvec4(p, 1.0));
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    Aabb out;
    const glm::dvec3 pad = 4.0 * double(kMachineEps) * (glm::abs(lo) + glm::abs(hi));
    out.lo = Vec3(lo - pad);
    out.hi = Vec3(hi + pad);
    return out;
}

}  // namespace

void Scene::buildInstances() {
    // Static (node < 0) meshes and every sphere in instance 0; each animated node's rigid
    // meshes together; each deforming mesh's node together (a skinned mesh's primitives share
    // its node and skin).
    using Key = std::tuple<int, int, bool>;  // model, node, rigid
    std::map<Key, uint32_t> byNode;
    std::vector<uint32_t> meshInstance(meshes.size());
    // (Present whenever some mesh never moves, even with no triangle: instance 0 then holds it.)
    bool anyStatic = !spheres.empty();
    for (const TriangleMesh& m : meshes) anyStatic |= m.node < 0;
    if (anyStatic) instances_.emplace_back();
    for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
        const TriangleMesh& m = meshes[mi];
        if (m.node < 0) {
            meshInstance[mi] = 0;
            continue;
        }
        const bool rigid = rigidMesh(m);
        auto [it, added] = byNode.emplace(Key{m.model, m.node, rigid}, uint32_t(instances_.size()));
        if (added) {
            SceneInstance in;
            in.kind = rigid ? SceneInstance::Kind::Rigid : SceneInstance::Kind::Deforming;
            in.model = m.model;
            in.node = m.node;
            in.transformed = rigid;
            instances_.push_back(std::move(in));
        }
        meshInstance[mi] = it->second;
    }
    for (uint32_t mi = 0; mi < meshes.size(); ++mi) instances_[meshInstance[mi]].meshes.push_back(mi);
    primInstance_.assign(size_t(nTri_) + nSph_, 0);
    uint32_t slot = 0;
    for (uint32_t i = 0; i < instances_.size(); ++i) {
        SceneInstance& in = instances_[i];
        for (uint32_t mi : in.meshes)
            for (uint32_t t = 0; t < meshes[mi].triangleCount(); ++t) in.prims.push_back(meshPrimBegin_[mi] + t);
        if (in.kind == SceneInstance::Kind::Static)
            for (uint32_t k = 0; k < nSph_; ++k) in.prims.push_back(nTri_ + k);
        for (uint32_t p : in.prims) primInstance_[p] = i;
        in.slotBase = slot;
        slot += uint32_t(in.prims.size());
    }
    slotPrim_.assign(slot, 0);
    slotVerts_.assign(3 * size_t(slot), Vec3(0.f));
    for (SceneInstance& in : instances_) {
        std::vector<Aabb>& boxes = scratchBoxes_;
        boxes.clear();
        if (in.kind == SceneInstance::Kind::Rigid) {
            // The object-space copies, the tree rays reach through the node's matrix.
            for (uint32_t mi : in.meshes) {
                const TriangleMesh& m = meshes[mi];
                for (size_t t = 0; t < m.triangleCount(); ++t)
                    boxes.push_back(triangleBox(m.objectPositions[m.indices[3 * t]], m.objectPositions[m.indices[3 * t + 1]],
                                                m.objectPositions[m.indices[3 * t + 2]]));
            }
        } else {
            for (uint32_t p : in.prims)
                boxes.push_back(p < nTri_ ? triangleBox(triVerts_[3 * size_t(p)], triVerts_[3 * size_t(p) + 1], triVerts_[3 * size_t(p) + 2])
                                          : sphereBox(spheres[p - nTri_]));
        }
        in.bvh.build(boxes);
        in.built = in.kind == SceneInstance::Kind::Rigid ? Bvh{} : in.bvh;
        in.bvhFrom = SceneInstance::kNoTree;  // (a first refit copies built's 4-wide shape too)
        in.builtCost = in.bvh.sahCost();
        in.lastRebuilt = false;
        fillInstanceSlots(in);
        if (in.kind == SceneInstance::Kind::Rigid) {
            placeRigid(in);
        } else {
            in.box = in.bvh.bounds();
            in.hidden = in.bvh.empty();
        }
    }
    buildTopLevel();
}

void Scene::fillInstanceSlots(SceneInstance& in) {
    fillSlots(in);
    buildLeafTriangles(in);
}

void Scene::fillSlots(SceneInstance& in) {
    const std::vector<uint32_t>& order = in.bvh.primIndex();
    Vec3* verts = slotVerts_.data() + 3 * size_t(in.slotBase);
    if (in.kind == SceneInstance::Kind::Rigid) {
        // Object-space vertices in the render-space triangles' corner order (the same indices).
        for (uint32_t s = 0; s < order.size(); ++s) {
            const uint32_t p = in.prims[order[s]];
            slotPrim_[in.slotBase + s] = p;
            const TriangleMesh& m = meshes[triMesh_[p]];
            const uint32_t* idx = &m.indices[3 * size_t(triLocal_[p])];
            for (int c = 0; c < 3; ++c) verts[3 * size_t(s) + c] = m.objectPositions[idx[c]];
        }
    } else {
        for (uint32_t s = 0; s < order.size(); ++s) {
            const uint32_t p = in.prims[order[s]];
            slotPrim_[in.slotBase + s] = p;
            if (p < nTri_)
                for (int c = 0; c < 3; ++c) verts[3 * size_t(s) + c] = triVerts_[3 * size_t(p) + c];
        }
    }
}

void Scene::buildLeafTriangles(SceneInstance& in) {
    const Vec3* verts = slotVerts_.data() + 3 * size_t(in.slotBase);
    // Only the static instance holds spheres; the others' slots are all triangles.
    if (in.kind != SceneInstance::Kind::Static || nSph_ == 0) {
        in.leafTris.build(in.bvh, verts, {});
        return;
    }
    const uint32_t base = in.slotBase;
    in.leafTris.build(in.bvh, verts, [&](uint32_t s) { return slotPrim_[base + s] < nTri_; });
}

void Scene::refitInstance(SceneInstance& in, const Bvh* base, double baseCost, std::pair<int, int> baseKey) {
    std::vector<Aabb>& boxes = scratchBoxes_;
    auto primBoxes = [&] {
        boxes.clear();
        for (uint32_t p : in.prims)
            boxes.push_back(p < nTri_ ? triangleBox(triVerts_[3 * size_t(p)], triVerts_[3 * size_t(p) + 1], triVerts_[3 * size_t(p) + 2])
                                      : sphereBox(spheres[p - nTri_]));
    };
    // Always from a fixed tree (build()'s, or an anchor pose's), never from an earlier frame's:
    // the result is then a function of this frame's pose alone.
    if (!base) base = &in.built, baseCost = in.builtCost, baseKey = SceneInstance::kBuiltTree;
    const bool triangles = in.kind == SceneInstance::Kind::Deforming;  // nothing but triangles
    if (triangles) {
        // The starting tree's topology (copied unless bvh already has it: a refit rewrites
        // every box) and the 4-wide shape collapsed from its own boxes.
        if (in.bvhFrom != baseKey || baseKey == SceneInstance::kNoTree) in.bvh = *base;
        in.bvhFrom = baseKey;
        // The slots first (the starting tree's leaf order, which a refit keeps), then the leaf
        // boxes from their contiguous vertices: one scattered pass over the triangles, not two.
        fillSlots(in);
        const Vec3* v = slotVerts_.data() + 3 * size_t(in.slotBase);
        boxes.resize(in.prims.size());
        for (size_t k = 0; k < boxes.size(); ++k) boxes[k] = triangleBox(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
        in.bvh.refitBySlotKeepShape(boxes);
    } else {
        in.bvh = *base;
        in.bvhFrom = SceneInstance::kNoTree;
        primBoxes();
        in.bvh.refit(boxes);
    }
    in.lastSahRatio = baseCost > 0.0 ? in.bvh.sahCost() / baseCost : 0.0;
    in.lastRebuilt = baseCost > 0.0 && in.lastSahRatio > rebuildGrowth;
    if (in.lastRebuilt) {
        if (triangles) primBoxes();
        in.bvh.build(boxes);
        in.bvhFrom = SceneInstance::kNoTree;
        fillInstanceSlots(in);
    } else if (triangles) {
        buildLeafTriangles(in);
    } else {
        fillInstanceSlots(in);
    }
    in.box = in.bvh.bounds();
    in.hidden = in.bvh.empty();
}

void Scene::placeRigid(SceneInstance& in) {
    const DMat4& renderFromObject = meshes[in.meshes[0]].renderFromObject;
    const double det = glm::determinant(glm::dmat3(renderFromObject));
    // A node scaled to nothing (or to infinity) shows nothing this frame; the loader drops such
    // meshes at rest, and a pose may pass through one.
    in.hidden = !(std::abs(det) > 0.0) || !std::isfinite(det) || in.bvh.empty();
    if (in.hidden) {
        in.box = Aabb{};
        return;
    }
    in.objectFromRender = glm::inverse(renderFromObject);
    in.box = transformedBox(in.bvh.bounds(), renderFromObject);
}

void Scene::buildTopLevel() {
    twoLevel_ = !(instances_.size() == 1 && !instances_[0].transformed);
    if (!twoLevel_) return;
    // One instance per leaf: the walk then visits them front to back. Hidden ones are left out
    // (an empty box would read as all of space).
    std::vector<Aabb> boxes;
    topInstance_.clear();
    for (uint32_t i = 0; i < instances_.size(); ++i)
        if (!instances_[i].hidden) {
            boxes.push_back(instances_[i].box);
            topInstance_.push_back(i);
        }
    top_.build(boxes, 1);
}

}  // namespace rf
