// The scene geometry's two-level acceleration structure (scene_instance.h): build, refit and
// posing; which primitives go into which instance, each instance's tree and slots, rigid
// instances moved by their node's matrix, and the top level over them.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <tuple>

#include "engine/geometry/prim_bounds.h"
#include "engine/geometry/skinning.h"
#include "engine/scene/scene_geometry.h"
#include "engine/util/load_control.h"

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

uint64_t nextGeometryVersion() {
    static std::atomic<uint64_t> counter{0};
    return ++counter;
}

/// Neither plane cuts the sphere (one may touch it).
bool noPlaneCuts(const std::vector<Plane>& planes, const Sphere& a) {
    for (const Plane& pl : planes)
        if (std::abs(glm::dot(DVec3(pl.n), DVec3(a.center)) + double(pl.d)) < double(a.radius)) return false;
    return true;
}
bool spheresOverlap(const Sphere& a, const Sphere& b) {
    return glm::length(DVec3(a.center) - DVec3(b.center)) < double(a.radius) + b.radius;
}

}  // namespace

void SceneGeometry::build(const std::vector<Material>& materials, const TextureSet& textures) {
    LoadStep step("building the BVH");
    version_ = nextGeometryVersion();
    triVerts_.clear();
    triMesh_.clear();
    triLocal_.clear();
    meshPrimBegin_.assign(meshes.size(), 0);
    meshMasked_.assign(meshes.size(), 0);
    anyMasked_ = false;
    maskMaterials_.clear();
    maskTextures_ = TextureSet{};
    for (size_t m = 0; m < meshes.size(); ++m) {
        const TriangleMesh& mesh = meshes[m];
        const int mat = mesh.material;
        if (mat >= 0 && mat < static_cast<int>(materials.size()) && materials[mat].alphaMode == AlphaMode::Mask) {
            meshMasked_[m] = 1;
            anyMasked_ = true;
        }
        meshPrimBegin_[m] = static_cast<uint32_t>(triMesh_.size());
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            if (t % 65536 == 0) pollLoadCancel();
            for (int k = 0; k < 3; ++k) triVerts_.push_back(mesh.positions[mesh.indices[3 * t + k]]);
            triMesh_.push_back(static_cast<uint32_t>(m));
            triLocal_.push_back(static_cast<uint32_t>(t));
        }
    }
    if (anyMasked_) {
        maskMaterials_ = materials;
        maskTextures_ = textures;
    }
    nTri_ = static_cast<uint32_t>(triMesh_.size());
    nSph_ = static_cast<uint32_t>(spheres.size());
    const size_t nPrims = triMesh_.size() + spheres.size();
    useBvh_ = nPrims >= kBvhThreshold;
    instances_.clear();
    top_ = Bvh{};
    twoLevel_ = false;
    lastRebuilt_ = false;
    if (useBvh_) {
        buildInstances();
        LoadStep overlaps("checking which spheres overlap");
        findAloneSpheres();
        return;
    }
    slotPrim_.resize(nPrims);
    for (uint32_t i = 0; i < nPrims; ++i) slotPrim_[i] = i;
    // Spare lanes get a negative reach: they never pass the pre-test.
    for (size_t i = 0; i < kBvhThreshold; ++i) {
        const bool used = i < spheres.size();
        const Sphere s = used ? spheres[i] : Sphere{};
        sphX_[i] = s.center.x;
        sphY_[i] = s.center.y;
        sphZ_[i] = s.center.z;
        const float err = 32.f * kMachineEps * (maxComponent(absComponents(s.center)) + s.radius);
        sphReach_[i] = used ? s.radius + err : -kInf;
        sphInner_[i] = used ? s.radius - err : -kInf;
    }
    findAloneSpheres();
    fillSlotData();
}

void SceneGeometry::findAloneSpheres() {
    sphereAlone_.assign(spheres.size(), 0);
    if (!triMesh_.empty()) return;  // the fast path is for scenes of spheres and planes only
    if (!useBvh_) {
        for (size_t i = 0; i < spheres.size(); ++i) {
            bool alone = noPlaneCuts(planes, spheres[i]);
            for (size_t j = 0; j < spheres.size() && alone; ++j) alone = j == i || !spheresOverlap(spheres[i], spheres[j]);
            sphereAlone_[i] = alone;
        }
        return;
    }
    // With the BVH (its primitives are the spheres, in order): each sphere looks only at the
    // spheres whose boxes meet its box, n log n rather than every pair (10⁵ spheres took 37 s).
    // The float boxes may sit a rounding step inside the true ones: the query box is widened
    // by well over that (relative to the scene's largest coordinate), and the exact test in
    // double decides.
    float scale = 0.f;
    for (const Sphere& s : spheres) scale = std::max(scale, maxComponent(absComponents(s.center)) + s.radius);
    const float widen = 8.f * kMachineEps * scale;
    // Spheres with no triangles: the one static instance, its primitives the spheres in order.
    const std::vector<BvhNode>& nodes = instances_[0].bvh.nodes();
    const std::vector<uint32_t>& prims = instances_[0].bvh.primIndex();
    std::vector<uint32_t> stack;
    for (size_t i = 0; i < spheres.size(); ++i) {
        if (i % 4096 == 0) pollLoadCancel();
        const Sphere& a = spheres[i];
        if (!noPlaneCuts(planes, a)) continue;
        const Vec3 lo = a.center - Vec3(a.radius + widen), hi = a.center + Vec3(a.radius + widen);
        bool alone = true;
        stack.assign(1, 0u);
        while (!stack.empty() && alone) {
            const BvhNode& nd = nodes[stack.back()];
            const uint32_t at = stack.back();
            stack.pop_back();
            if (nd.box.lo.x > hi.x || nd.box.lo.y > hi.y || nd.box.lo.z > hi.z || nd.box.hi.x < lo.x || nd.box.hi.y < lo.y ||
                nd.box.hi.z < lo.z)
                continue;
            if (nd.count == 0) {
                stack.push_back(at + 1);
                stack.push_back(nd.offset);
                continue;
            }
            for (uint32_t k = nd.offset; k < nd.offset + nd.count && alone; ++k)
                alone = prims[k] == i || !spheresOverlap(a, spheres[prims[k]]);
        }
        sphereAlone_[i] = alone;
    }
}

void SceneGeometry::fillSlotData() {
    // Without a BVH the slots are the primitives in order.
    const uint32_t nTri = static_cast<uint32_t>(triMesh_.size());
    slotVerts_.assign(3 * slotPrim_.size(), Vec3(0.f));
    for (size_t i = 0; i < slotPrim_.size(); ++i) {
        const uint32_t p = slotPrim_[i];
        if (p >= nTri) continue;
        for (int k = 0; k < 3; ++k) slotVerts_[3 * i + k] = triVerts_[3 * p + k];
    }
}

void SceneGeometry::gatherTriangles(uint32_t m) {
    const TriangleMesh& mesh = meshes[m];
    Vec3* out = triVerts_.data() + 3 * size_t(meshPrimBegin_[m]);
    for (size_t i = 0; i < mesh.indices.size(); ++i) out[i] = mesh.positions[mesh.indices[i]];
}

void SceneGeometry::refit() {
    version_ = nextGeometryVersion();
    for (uint32_t m = 0; m < meshes.size(); ++m) gatherTriangles(m);
    lastRebuilt_ = false;
    if (!useBvh_) {
        fillSlotData();
        return;
    }
    for (SceneInstance& in : instances_) {
        if (in.kind == SceneInstance::Kind::Rigid) placeRigid(in);
        else refitInstance(in);
        lastRebuilt_ |= in.lastRebuilt;
    }
    buildTopLevel();
}

void SceneGeometry::poseModel(int model, const std::vector<DMat4>& renderFromNode, const std::vector<std::vector<double>>& morphWeights,
                      const SceneInstance* only, std::vector<uint8_t>* moved) {
    // Joint matrices once per skin, from the same node matrices as the rigid meshes.
    std::vector<std::vector<DMat4>> joints;
    const std::vector<Skin>* skins = model >= 0 && size_t(model) < models.size() ? &models[size_t(model)].skins : nullptr;
    auto poseOne = [&](uint32_t mi) {
        TriangleMesh& mesh = meshes[mi];
        if (mesh.model != model || mesh.node < 0 || mesh.node >= static_cast<int>(renderFromNode.size())) return;
        const std::vector<DMat4>* jm = nullptr;
        const bool hidden = renderFromNode[size_t(mesh.node)][3][3] == 0.0;  // a zero matrix (applyNodeTransforms)
        if (!hidden && mesh.skin >= 0 && skins && size_t(mesh.skin) < skins->size()) {
            if (joints.empty()) joints.resize(skins->size());
            std::vector<DMat4>& j = joints[size_t(mesh.skin)];
            if (j.empty()) j = jointMatrices((*skins)[size_t(mesh.skin)], renderFromNode);
            jm = &j;
        }
        const std::vector<double>* w = (mesh.node < static_cast<int>(morphWeights.size())) ? &morphWeights[mesh.node] : nullptr;
        poseMesh(mesh, renderFromNode[size_t(mesh.node)], jm, w);
        gatherTriangles(mi);
        if (moved) (*moved)[mi] = 1;
    };
    if (only)
        for (uint32_t mi : only->meshes) poseOne(mi);
    else
        for (uint32_t mi = 0; mi < meshes.size(); ++mi) poseOne(mi);
}

const SceneInstance::AnchorTree& SceneGeometry::anchorTree(SceneInstance& in, const PoseAnchor& anchor, std::vector<DMat4>& anchorNodes,
                                                   std::vector<std::vector<double>>& anchorWeights) {
    const auto key = std::make_pair(anchor.clip, anchor.index);
    auto it = in.anchors.find(key);
    if (it != in.anchors.end()) return it->second;
    if (anchorNodes.empty()) anchor.pose(anchorNodes, anchorWeights);
    // The instance's meshes at the anchor's pose (the frame's own pose overwrites them next).
    poseModel(in.model, anchorNodes, anchorWeights, &in, nullptr);
    std::vector<Aabb>& boxes = scratchBoxes_;
    boxes.clear();
    for (uint32_t p : in.prims)
        boxes.push_back(triangleBox(triVerts_[3 * size_t(p)], triVerts_[3 * size_t(p) + 1], triVerts_[3 * size_t(p) + 2]));
    SceneInstance::AnchorTree t;
    t.tree.build(boxes);
    t.cost = t.tree.sahCost();
    t.tree.dropWideNodes();
    return in.anchors.emplace(key, std::move(t)).first->second;
}

void SceneGeometry::applyNodeTransforms(int model, const std::vector<DMat4>& renderFromNode,
                                const std::vector<std::vector<double>>& morphWeights, const PoseAnchor* anchor) {
    using Clock = std::chrono::steady_clock;
    const Clock::time_point t0 = Clock::now();
    lastCost_ = UpdateCost{};
    // Anchor trees first (once per anchor and instance): they pose the meshes at the anchor.
    std::vector<const SceneInstance::AnchorTree*> base(instances_.size(), nullptr);
    if (anchor && anchor->pose && useBvh_) {
        std::vector<DMat4> anchorNodes;
        std::vector<std::vector<double>> anchorWeights;
        for (size_t i = 0; i < instances_.size(); ++i)
            if (instances_[i].kind == SceneInstance::Kind::Deforming && instances_[i].model == model) {
                const size_t had = instances_[i].anchors.size();
                base[i] = &anchorTree(instances_[i], *anchor, anchorNodes, anchorWeights);
                lastCost_.anchorsBuilt += int(instances_[i].anchors.size() - had);
            }
    }
    const Clock::time_point t1 = Clock::now();
    std::vector<uint8_t> moved(meshes.size(), 0);
    poseModel(model, renderFromNode, morphWeights, nullptr, &moved);
    const Clock::time_point t2 = Clock::now();
    lastCost_.poseS = std::chrono::duration<double>(t2 - t1).count();
    if (std::find(moved.begin(), moved.end(), 1) == moved.end()) return;
    version_ = nextGeometryVersion();
    lastRebuilt_ = false;
    if (!useBvh_) {
        fillSlotData();
        return;
    }
    // Only the instances of the meshes that moved: a static tree is never touched again.
    for (size_t i = 0; i < instances_.size(); ++i) {
        SceneInstance& in = instances_[i];
        if (in.kind == SceneInstance::Kind::Static || in.meshes.empty() || !moved[in.meshes[0]]) continue;
        if (in.kind == SceneInstance::Kind::Rigid) placeRigid(in);
        else if (base[i]) refitInstance(in, &base[i]->tree, base[i]->cost, {anchor->clip, anchor->index});
        else refitInstance(in);
        lastRebuilt_ |= in.lastRebuilt;
        if (in.kind == SceneInstance::Kind::Deforming) lastCost_.sahRatio = std::max(lastCost_.sahRatio, in.lastSahRatio);
    }
    buildTopLevel();
    lastCost_.treeS = std::chrono::duration<double>((t1 - t0) + (Clock::now() - t2)).count();
}

void SceneGeometry::buildInstances() {
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

void SceneGeometry::fillInstanceSlots(SceneInstance& in) {
    fillSlots(in);
    buildLeafTriangles(in);
}

void SceneGeometry::fillSlots(SceneInstance& in) {
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

void SceneGeometry::buildLeafTriangles(SceneInstance& in) {
    const Vec3* verts = slotVerts_.data() + 3 * size_t(in.slotBase);
    // Only the static instance holds spheres; the others' slots are all triangles.
    if (in.kind != SceneInstance::Kind::Static || nSph_ == 0) {
        in.leafTris.build(in.bvh, verts, {});
        return;
    }
    const uint32_t base = in.slotBase;
    in.leafTris.build(in.bvh, verts, [&](uint32_t s) { return slotPrim_[base + s] < nTri_; });
}

void SceneGeometry::refitInstance(SceneInstance& in, const Bvh* base, double baseCost, std::pair<int, int> baseKey) {
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

void SceneGeometry::placeRigid(SceneInstance& in) {
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

void SceneGeometry::buildTopLevel() {
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
