#include "engine/load/gltf/gltf_loader.h"

#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/scene/default_rig.h"
#include "engine/scene/env_lighting.h"
#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_accessors.h"
#include "engine/load/gltf/gltf_geometry.h"
#include "engine/load/gltf/gltf_lights_cameras.h"
#include "engine/util/load_control.h"
#include "engine/load/gltf/gltf_materials.h"
#include "engine/load/gltf/gltf_parse.h"
#include "engine/load/gltf/gltf_safety.h"
#include "engine/load/gltf/gltf_variants.h"
#include "engine/geometry/render_origin.h"
#include "engine/geometry/skinning.h"

namespace rf {

namespace {

using namespace gltf;

bool finiteMat(const DMat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

/// A glTF file parsed and checked, with its node hierarchy resolved; turned into scene content
/// by addTo().
class GltfModel {
public:
    GltfModel(const std::string& path, FileSource& fs, const AssetOptions& assets) : path_(path), assets_(assets) {
        model_ = parseGltf(path, fs, assets, notes_);
        pollLoadCancel();
        LoadStep resolving("resolving its node hierarchy");
        chooseMaterialVariant();
        resolveHierarchy();
        checkInstancedSize();
        readAnimations();
        readSkins();
    }

    /// World-space bounds of the drawn triangles; false if there are none.
    bool bounds(const DMat4& worldFromModel, glm::dvec3& lo, glm::dvec3& hi) {
        lo = glm::dvec3(std::numeric_limits<double>::infinity());
        hi = -lo;
        bool any = false;
        LoadStep step("reading its meshes");
        for (int node : order_) {
            pollLoadCancel();
            const tinygltf::Node& n = model_.nodes[size_t(node)];
            if (n.mesh < 0) continue;
            const DMat4 m = worldFromModel * modelFromNode_[size_t(node)];
            for (size_t p = 0; p < model_.meshes[size_t(n.mesh)].primitives.size(); ++p) {
                const PrimitiveGeometry* g = primitive(n.mesh, int(p));
                if (!g) continue;
                std::vector<Vec3> pos = morphedPositions(g->mesh, defaultWeights(node));
                const bool skinned = skinnedPrimitive(node, *g, int(p));
                if (skinned) pos = restSkinned(node, *g, worldFromModel).positions;
                for (uint32_t i : g->mesh.indices) {
                    const glm::dvec3 q = skinned ? glm::dvec3(pos[i]) : glm::dvec3(m * glm::dvec4(glm::dvec3(pos[i]), 1.0));
                    lo = glm::min(lo, q);
                    hi = glm::max(hi, q);
                    any = true;
                }
            }
        }
        return any && std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z);
    }

    /// How many material variants the file names (KHR_materials_variants).
    size_t variantCount() const { return materialVariants(model_).size(); }

    /// materialOverride ≥ 0: every primitive in that scene material, the file's left unread.
    void addTo(Scene& scene, const DMat4& worldFromModel, int materialOverride = -1);

    /// Why bounds() found nothing to draw, for the error message.
    std::string emptyReason() const {
        size_t nonFinite = 0, degenerate = 0, outside = 0;
        for (const auto& [key, g] : prims_)
            if (g) nonFinite += g->droppedNonFinite, degenerate += g->droppedDegenerate, outside += g->outsideBounds;
        if (outside)
            return "the model has no triangles to render (" + std::to_string(outside) +
                   " vertices lie outside POSITION's declared min/max: corrupt data?)";
        if (nonFinite) return "the model has no triangles to render (" + std::to_string(nonFinite) + " have non-finite positions)";
        if (degenerate) return "the model has no triangles to render (" + std::to_string(degenerate) + " are degenerate)";
        if (skippedPointsLines_) return "the model has no triangles to render (points and lines are not rendered)";
        if (order_.empty()) return "the model's scene has no nodes, so there is nothing to render";
        return "the model has no triangles to render";
    }

private:
    const PrimitiveGeometry* primitive(int mesh, int prim) {
        const auto key = std::make_pair(mesh, prim);
        auto it = prims_.find(key);
        if (it == prims_.end()) {
            PrimitiveGeometry g;
            const bool triangles = buildPrimitive(model_, mesh, prim, path_, g, materialOverride_ < 0);
            it = prims_.emplace(key, triangles ? std::optional<PrimitiveGeometry>(std::move(g)) : std::nullopt).first;
            if (!triangles) skippedPointsLines_ = true;
            else notePrimitive(*it->second, "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(prim) + "]");
        }
        return it->second ? &*it->second : nullptr;
    }

    /// Data a loader could silently work around, said once per primitive.
    void notePrimitive(const PrimitiveGeometry& g, const std::string& w) {
        if (g.outsideBounds)
            notes_.push_back(w + ": " + std::to_string(g.outsideBounds) +
                             " vertices lie outside POSITION's declared min/max (corrupt data?); their triangles dropped");
        if (g.boundsMissing) notes_.push_back(w + ": POSITION has no min/max (glTF requires them); positions not checked");
        if (g.leftoverIndices)
            notes_.push_back(w + ": " + std::to_string(g.leftoverIndices) + " trailing indices ignored (TRIANGLES needs a multiple of 3)");
        if (g.materialOutOfRange)
            notes_.push_back(w + ".material: no such material (" + std::to_string(model_.materials.size()) +
                             " in the file); drawn with the default material");
    }

    std::vector<double> defaultWeights(int node) const {
        const tinygltf::Node& n = model_.nodes[size_t(node)];
        if (!n.weights.empty()) return n.weights;
        return n.mesh >= 0 ? model_.meshes[size_t(n.mesh)].weights : std::vector<double>{};
    }

    DMat4 localTransform(int i) const {
        const tinygltf::Node& n = model_.nodes[size_t(i)];
        const std::string w = "nodes[" + std::to_string(i) + "]";
        DMat4 m(1.0);
        if (n.matrix.size() == 16) {
            m = glm::make_mat4(n.matrix.data());  // both column-major
        } else {
            if (!n.matrix.empty()) throw InputError(path_, w + ".matrix: expected 16 numbers");
            DMat4 t(1.0), r(1.0), s(1.0);
            if (n.translation.size() == 3) t = glm::translate(DMat4(1.0), glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
            if (n.rotation.size() == 4) {
                DQuat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF xyzw → glm wxyz
                const double len = glm::length(q);
                if (!(len > 0.0) || !std::isfinite(len)) throw InputError(path_, w + ".rotation: not a usable quaternion");
                r = glm::mat4_cast(q / len);
            }
            if (n.scale.size() == 3) s = glm::scale(DMat4(1.0), glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
            m = t * r * s;
        }
        if (!finiteMat(m)) throw InputError(path_, w + ": non-finite transform");
        return m;
    }

    /// Whether primitive prim of node's mesh is drawn through the node's skin: the node has one
    /// and the primitive has JOINTS_n/WEIGHTS_n. Refuses joint indices the skin lacks.
    bool skinnedPrimitive(int node, const PrimitiveGeometry& g, int prim) const {
        const tinygltf::Node& n = model_.nodes[size_t(node)];
        if (n.skin < 0 || g.mesh.influences == 0) return false;
        const size_t joints = skins_[size_t(n.skin)].joints.size();
        for (const PrimitiveGeometry::JointSet& js : g.jointSets)
            if (js.maxJoint >= joints)
                throw InputError(path_, "meshes[" + std::to_string(n.mesh) + "].primitives[" + std::to_string(prim) + "].attributes.JOINTS_" +
                                            std::to_string(js.set) + " (accessors[" + std::to_string(js.accessor) + "]): vertex " +
                                            std::to_string(js.vertex) + " names joint " + std::to_string(js.maxJoint) + ", but skins[" +
                                            std::to_string(n.skin) + "] (used by nodes[" + std::to_string(node) + "]) has " +
                                            std::to_string(joints) + " joints");
        return true;
    }

    /// A skinned primitive posed by its skin's rest joints (and the node's default morph
    /// weights), with its object-space copies kept.
    TriangleMesh restSkinned(int node, const PrimitiveGeometry& g, const DMat4& renderFromModel) const {
        TriangleMesh m = g.mesh;
        m.skin = model_.nodes[size_t(node)].skin;
        m.objectPositions = m.positions;
        m.objectNormals = m.normals;
        m.objectTangents = m.tangents;
        std::vector<DMat4> renderFromNode(restModelFromNode_.size());
        for (size_t i = 0; i < renderFromNode.size(); ++i) renderFromNode[i] = renderFromModel * restModelFromNode_[i];
        const std::vector<DMat4> joints = jointMatrices(skins_[size_t(m.skin)], renderFromNode);
        const std::vector<double> w = defaultWeights(node);
        poseMesh(m, DMat4(1.0), &joints, &w);
        return m;
    }

    /// skins[]: joints that are nodes, inverse bind matrices (MAT4 floats, one per joint, or
    /// the identity when absent), and the nodes that name them; the rest pose of every node
    /// (joints need not be in the drawn scene).
    void readSkins() {
        for (size_t s = 0; s < model_.skins.size(); ++s) {
            const tinygltf::Skin& gs = model_.skins[s];
            const std::string w = "skins[" + std::to_string(s) + "]";
            Skin skin;
            skin.name = gs.name;
            if (gs.joints.empty()) throw InputError(path_, w + ".joints: a skin needs at least one joint");
            for (size_t j = 0; j < gs.joints.size(); ++j) {
                const int node = gs.joints[j];
                if (node < 0 || size_t(node) >= model_.nodes.size())
                    throw InputError(path_, w + ".joints[" + std::to_string(j) + "]: no node " + std::to_string(node));
                skin.joints.push_back(node);
            }
            skin.inverseBind.assign(gs.joints.size(), DMat4(1.0));
            if (gs.inverseBindMatrices >= 0) {
                const AccessorData ibm = readAccessor(model_, gs.inverseBindMatrices, path_, {TINYGLTF_TYPE_MAT4});
                if (ibm.count < gs.joints.size())
                    throw InputError(path_, w + ".inverseBindMatrices (accessors[" + std::to_string(gs.inverseBindMatrices) + "]): " +
                                                std::to_string(ibm.count) + " matrices for " + std::to_string(gs.joints.size()) + " joints");
                for (size_t j = 0; j < gs.joints.size(); ++j) {
                    DMat4 m;
                    for (int c = 0; c < 16; ++c) m[c / 4][c % 4] = ibm.at(j, c);  // column-major, as glTF stores it
                    if (!finiteMat(m))
                        throw InputError(path_, w + ".inverseBindMatrices (accessors[" + std::to_string(gs.inverseBindMatrices) + "]): matrix " +
                                                    std::to_string(j) + " is not finite");
                    skin.inverseBind[j] = m;
                }
            }
            skins_.push_back(std::move(skin));
        }
        for (size_t i = 0; i < model_.nodes.size(); ++i)
            if (model_.nodes[i].skin >= 0 && size_t(model_.nodes[i].skin) >= skins_.size())
                throw InputError(path_, "nodes[" + std::to_string(i) + "].skin: no skin " + std::to_string(model_.nodes[i].skin));
        if (skins_.empty()) return;
        // Parents are acyclic (resolveHierarchy): a memoized walk up each chain.
        const size_t n = model_.nodes.size();
        restModelFromNode_.assign(n, DMat4(1.0));
        std::vector<uint8_t> done(n, 0);
        for (size_t i = 0; i < n; ++i) {
            if (i % 4096 == 0) pollLoadCancel();
            std::vector<size_t> chain;
            for (int k = int(i); k >= 0 && !done[size_t(k)]; k = parent_[size_t(k)]) chain.push_back(size_t(k));
            for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
                const int p = parent_[*it];
                restModelFromNode_[*it] = p >= 0 ? restModelFromNode_[size_t(p)] * localTransform(int(*it)) : localTransform(int(*it));
                if (!finiteMat(restModelFromNode_[*it])) throw InputError(path_, "nodes[" + std::to_string(*it) + "]: transform overflows");
                done[*it] = 1;
            }
        }
    }

    void resolveHierarchy() {
        const size_t n = model_.nodes.size();
        parent_.assign(n, -1);
        for (size_t i = 0; i < n; ++i) {
            if (i % 4096 == 0) pollLoadCancel();
            for (int c : model_.nodes[i].children) {
                if (c < 0 || size_t(c) >= n)
                    throw InputError(path_, "nodes[" + std::to_string(i) + "].children: no node " + std::to_string(c));
                if (size_t(c) == i || parent_[size_t(c)] != -1)
                    throw InputError(path_, "nodes[" + std::to_string(c) + "] has more than one parent (the node graph must be a tree)");
                parent_[size_t(c)] = int(i);
            }
        }
        // Every node has at most one parent, so walking up from each node either reaches a
        // root or comes back to a node of the same walk (a cycle). Nodes of finished walks are
        // known to reach a root: each node is walked once, linear even in a 10⁶-node chain.
        {
            enum : uint8_t { kUnseen, kOnWalk, kReachesRoot };
            std::vector<uint8_t> state(n, kUnseen);
            std::vector<int> walk;
            for (size_t i = 0; i < n; ++i) {
                if (i % 4096 == 0) pollLoadCancel();
                walk.clear();
                int p = int(i);
                while (p >= 0 && state[size_t(p)] == kUnseen) {
                    state[size_t(p)] = kOnWalk;
                    walk.push_back(p);
                    p = parent_[size_t(p)];
                }
                if (p >= 0 && state[size_t(p)] == kOnWalk)
                    throw InputError(path_, "nodes[" + std::to_string(i) + "]: the node hierarchy has a cycle");
                for (int w : walk) state[size_t(w)] = kReachesRoot;
            }
        }
        std::vector<int> roots;
        if (model_.defaultScene >= 0 && size_t(model_.defaultScene) >= model_.scenes.size())
            throw InputError(path_, "scene: " + std::to_string(model_.defaultScene) + " is not one of the file's " +
                                        std::to_string(model_.scenes.size()) + " scenes");
        const int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : model_.scenes.empty() ? -1 : 0;
        if (sceneIndex < 0) {
            for (size_t i = 0; i < n; ++i)
                if (parent_[i] < 0) roots.push_back(int(i));
            if (n > 0) notes_.push_back("no scene defined: drawing every root node");
        } else {
            for (int r : model_.scenes[size_t(sceneIndex)].nodes) {
                if (r < 0 || size_t(r) >= n)
                    throw InputError(path_, "scenes[" + std::to_string(sceneIndex) + "].nodes: no node " + std::to_string(r));
                if (parent_[size_t(r)] >= 0) {
                    notes_.push_back("scene lists non-root nodes[" + std::to_string(r) + "]; drawn once, under its parent");
                    continue;
                }
                roots.push_back(r);
            }
        }
        modelFromNode_.assign(n, DMat4(1.0));
        std::vector<uint8_t> seen(n, 0);
        std::vector<int> stack(roots.rbegin(), roots.rend());
        while (!stack.empty()) {
            if (order_.size() % 4096 == 0) pollLoadCancel();
            const int i = stack.back();
            stack.pop_back();
            if (seen[size_t(i)]) continue;
            seen[size_t(i)] = 1;
            const DMat4 local = localTransform(i);
            modelFromNode_[size_t(i)] = parent_[size_t(i)] >= 0 ? modelFromNode_[size_t(parent_[size_t(i)])] * local : local;
            if (!finiteMat(modelFromNode_[size_t(i)])) throw InputError(path_, "nodes[" + std::to_string(i) + "]: transform overflows");
            order_.push_back(i);
            const auto& ch = model_.nodes[size_t(i)].children;
            for (auto it = ch.rbegin(); it != ch.rend(); ++it) stack.push_back(*it);
            const int mesh = model_.nodes[size_t(i)].mesh;
            if (mesh >= 0 && size_t(mesh) >= model_.meshes.size())
                throw InputError(path_, "nodes[" + std::to_string(i) + "].mesh: no mesh " + std::to_string(mesh));
        }
    }

    /// Refuses models whose nodes instance more triangles than the cap, from accessor counts
    /// alone, before any geometry is built (nodes sharing a big mesh multiply it).
    void checkInstancedSize() const {
        uint64_t tris = 0;
        for (int node : order_) {
            const int mesh = model_.nodes[size_t(node)].mesh;
            if (mesh < 0) continue;
            for (const tinygltf::Primitive& p : model_.meshes[size_t(mesh)].primitives) {
                int acc = p.indices;
                if (acc < 0)
                    if (auto it = p.attributes.find("POSITION"); it != p.attributes.end()) acc = it->second;
                if (acc >= 0 && size_t(acc) < model_.accessors.size()) tris += model_.accessors[size_t(acc)].count;
            }
        }
        tris /= 3;  // an upper bound for strips and fans as well, within two per primitive
        if (tris > Limits::kMaxTriangles)
            throw InputError(path_, "about " + std::to_string(tris) + " triangles once nodes instance their meshes, over the limit of " +
                                        std::to_string(Limits::kMaxTriangles));
    }

    void readAnimations() {
        animatedNode_.assign(model_.nodes.size(), 0);
        for (size_t a = 0; a < model_.animations.size(); ++a) {
            const tinygltf::Animation& ga = model_.animations[a];
            const std::string wa = "animations[" + std::to_string(a) + "]";
            Animation anim;
            anim.name = ga.name;
            // Sampler components depend on the channel's path; find them first.
            std::vector<int> comps(ga.samplers.size(), 0);
            for (size_t c = 0; c < ga.channels.size(); ++c) {
                const tinygltf::AnimationChannel& ch = ga.channels[c];
                const std::string wc = wa + ".channels[" + std::to_string(c) + "]";
                if (ch.target_node < 0) continue;  // targets something else (extension): nothing to move
                if (size_t(ch.target_node) >= model_.nodes.size()) throw InputError(path_, wc + ".target.node: no such node");
                if (ch.sampler < 0 || size_t(ch.sampler) >= ga.samplers.size()) throw InputError(path_, wc + ".sampler: no such sampler");
                AnimChannel out;
                out.sampler = ch.sampler;
                out.node = ch.target_node;
                int k = 0;
                if (ch.target_path == "translation") out.path = AnimPath::Translation, k = 3;
                else if (ch.target_path == "rotation") out.path = AnimPath::Rotation, k = 4;
                else if (ch.target_path == "scale") out.path = AnimPath::Scale, k = 3;
                else if (ch.target_path == "weights") out.path = AnimPath::Weights, k = -1;
                else throw InputError(path_, wc + ".target.path: \"" + ch.target_path + "\" is not a glTF path");
                comps[size_t(ch.sampler)] = k;
                anim.channels.push_back(out);
                animatedNode_[size_t(ch.target_node)] = 1;
            }
            for (size_t s = 0; s < ga.samplers.size(); ++s) {
                const tinygltf::AnimationSampler& gs = ga.samplers[s];
                const std::string ws = wa + ".samplers[" + std::to_string(s) + "]";
                AnimSampler out;
                if (gs.interpolation == "STEP") out.interpolation = KeyInterpolation::Step;
                else if (gs.interpolation == "CUBICSPLINE") out.interpolation = KeyInterpolation::CubicSpline;
                else out.interpolation = KeyInterpolation::Linear;
                const AccessorData in = readAccessor(model_, gs.input, path_, {TINYGLTF_TYPE_SCALAR});
                const AccessorData val = readAccessor(model_, gs.output, path_, {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});
                out.times = in.values;
                out.values = val.values;
                for (float x : out.times)
                    if (!std::isfinite(x)) throw InputError(path_, ws + ".input: non-finite key time");
                for (float x : out.values)
                    if (!std::isfinite(x)) throw InputError(path_, ws + ".output: non-finite key value");
                const size_t perKey = out.interpolation == KeyInterpolation::CubicSpline ? 3 : 1;
                int k = comps[s];
                if (k < 0 && !out.times.empty()) k = int(out.values.size() / (out.times.size() * perKey));  // weights
                if (k == 0) k = val.components;  // sampler no channel uses
                out.components = k;
                if (k <= 0 || out.values.size() != out.times.size() * perKey * size_t(k))
                    throw InputError(path_, ws + ": " + std::to_string(out.values.size()) + " output values do not match " +
                                                std::to_string(out.times.size()) + " keys");
                anim.samplers.push_back(std::move(out));
            }
            animations_.push_back(std::move(anim));
        }
    }

    /// Primitives and triangles the load left out, summed over the model for its notes.
    struct DropCounts {
        size_t degenerate = 0, nonFinite = 0, generated = 0, unplaced = 0;
    };
    SceneGraph sceneGraph(const DMat4& renderFromModel) const;
    void addNodeMeshes(Scene& scene, int node, const DMat4& renderFromNode, int modelIndex, bool dynamic,
                       MaterialBuilder& materials, DropCounts& dropped);
    void addNodeLightAndCamera(Scene& scene, int node, const DMat4& renderFromNode);
    void noteDrops(const DropCounts& d);
    /// assets_.variant as an index into the file's variants (variant_), refused if it has none
    /// by that name; without a choice, a note lists the variants the file offers.
    void chooseMaterialVariant() {
        const std::vector<std::string> names = materialVariants(model_);
        if (assets_.variant.empty()) {
            if (!names.empty())
                notes_.push_back("material variants " + listVariants(names) + "; showing the default materials (--variant NAME picks one)");
            return;
        }
        if (names.empty() && !assets_.variantRequired) return;
        variant_ = chooseVariant(model_, path_, assets_.variant, assets_.variantSource);
    }
    /// The file's material for primitive p of mesh under the chosen variant.
    int primitiveMaterial(const tinygltf::Mesh& mesh, size_t p, int loaded) const {
        return variant_ >= 0 ? variantMaterial(mesh.primitives[p], variant_) : loaded;
    }

    std::string path_;
    AssetOptions assets_;
    tinygltf::Model model_;
    std::vector<std::string> notes_;
    std::vector<int> parent_;
    std::vector<DMat4> modelFromNode_;
    std::vector<int> order_;  ///< drawn nodes, parents before children
    std::vector<uint8_t> animatedNode_;
    std::vector<Animation> animations_;
    std::vector<Skin> skins_;
    std::vector<DMat4> restModelFromNode_;  ///< every node's rest transform (filled when there are skins)
    size_t weightsNormalized_ = 0, weightsZero_ = 0;
    int variant_ = -1;  ///< the chosen KHR_materials_variants variant, −1 for none
    std::map<std::pair<int, int>, std::optional<PrimitiveGeometry>> prims_;
    bool skippedPointsLines_ = false;
    int materialOverride_ = -1;
};

/// The node hierarchy with its rest transforms and animations, for animated nodes to follow.
SceneGraph GltfModel::sceneGraph(const DMat4& renderFromModel) const {
    SceneGraph graph;
    graph.source = path_;
    graph.renderFromModel = renderFromModel;
    for (size_t i = 0; i < model_.nodes.size(); ++i) {
        const tinygltf::Node& n = model_.nodes[i];
        SceneNode sn;
        sn.name = n.name;
        sn.parent = parent_[i];
        if (n.matrix.size() == 16) {
            sn.useMatrix = true;
            sn.matrix = glm::make_mat4(n.matrix.data());
        }
        if (n.translation.size() == 3) sn.translation = glm::dvec3(n.translation[0], n.translation[1], n.translation[2]);
        if (n.rotation.size() == 4) sn.rotation = glm::normalize(DQuat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
        if (n.scale.size() == 3) sn.scale = glm::dvec3(n.scale[0], n.scale[1], n.scale[2]);
        sn.weights = defaultWeights(int(i));
        graph.nodes.push_back(std::move(sn));
    }
    graph.animations = animations_;
    graph.skins = skins_;
    return graph;
}

/// The node's mesh primitives, placed in render space; an animated node's keep their object
/// space copies so the timeline can move them.
void GltfModel::addNodeMeshes(Scene& scene, int node, const DMat4& renderFromNode, int modelIndex, bool dynamic,
                              MaterialBuilder& materials, DropCounts& dropped) {
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    if (n.mesh < 0) return;
    const tinygltf::Mesh& gm = model_.meshes[size_t(n.mesh)];
    for (size_t p = 0; p < gm.primitives.size(); ++p) {
        const PrimitiveGeometry* g = primitive(n.mesh, int(p));
        if (!g) continue;
        dropped.degenerate += g->droppedDegenerate;
        dropped.nonFinite += g->droppedNonFinite;
        dropped.generated += g->generatedNormals;
        if (g->mesh.indices.empty()) continue;
        if (skinnedPrimitive(node, *g, int(p))) {
            // The skin places it (the node's own transform is not used); it always keeps its
            // object-space data, so any animation of its joints can move it.
            TriangleMesh m = restSkinned(node, *g, scene.geometry.models[size_t(modelIndex)].renderFromModel);
            m.name = gm.name;
            m.model = modelIndex;
            m.node = node;
            bool finite = true;
            for (const Vec3& q : m.positions) finite &= isFinite(q);
            if (!finite) {
                ++dropped.unplaced;
                continue;
            }
            weightsNormalized_ += g->weightsNormalized;
            weightsZero_ += g->weightsZero;
            m.material = materialOverride_ >= 0 ? materialOverride_ : materials.materialFor(primitiveMaterial(gm, p, g->gltfMaterial));
            if (materialOverride_ >= 0) m.colors.clear(), m.tangents.clear(), m.objectTangents.clear();
            scene.geometry.meshes.push_back(std::move(m));
            continue;
        }
        TriangleMesh m = g->mesh;
        m.name = gm.name;
        m.influences = 0;  // not bound to a skin here: drawn rigidly by its node
        m.skinJoints.clear();
        m.skinWeights.clear();
        if (dynamic) {
            m.model = modelIndex;
            m.node = node;
            m.objectPositions = m.positions;
            m.objectNormals = m.normals;
            m.objectTangents = m.tangents;
            m.renderFromObject = renderFromNode;
        }
        if (!placePrimitive(m, renderFromNode, defaultWeights(node), !dynamic)) {
            ++dropped.unplaced;
            continue;
        }
        if (!dynamic) {
            m.morphPositions.clear();
            m.morphNormals.clear();
            m.morphTangents.clear();
        }
        if (materialOverride_ >= 0) {
            // One uniform material: the file's vertex colours and tangents have no part in it.
            m.material = materialOverride_;
            m.colors.clear();
            m.tangents.clear();
            m.objectTangents.clear();
        } else {
            m.material = materials.materialFor(primitiveMaterial(gm, p, g->gltfMaterial));
        }
        scene.geometry.meshes.push_back(std::move(m));
    }
}

/// The node's KHR_lights_punctual light and camera, if it has them.
void GltfModel::addNodeLightAndCamera(Scene& scene, int node, const DMat4& renderFromNode) {
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    if (auto it = n.extensions.find("KHR_lights_punctual"); it != n.extensions.end() && it->second.Has("light")) {
        const tinygltf::Value& li = it->second.Get("light");
        const int idx = li.IsInt() ? li.Get<int>() : -1;
        if (idx < 0 || size_t(idx) >= model_.lights.size())
            throw InputError(path_, "nodes[" + std::to_string(node) + "]: no light " + std::to_string(idx));
        scene.lights.push_back(punctualLight(model_.lights[size_t(idx)], renderFromNode, path_, idx));
    }
    if (n.camera >= 0) {
        if (size_t(n.camera) >= model_.cameras.size())
            throw InputError(path_, "nodes[" + std::to_string(node) + "].camera: no such camera");
        std::string why, fault;
        if (auto c = gltfCamera(model_.cameras[size_t(n.camera)], renderFromNode, why, fault)) {
            scene.gltfCameras.push_back(*c);
            scene.gltfCameraFaults.emplace_back(path_, fault.empty() ? fault : "cameras[" + std::to_string(n.camera) + "]." + fault);
        } else notes_.push_back("cameras[" + std::to_string(n.camera) + "]: " + why + "; skipped");
    }
}

/// What the load dropped or left out, as notes.
void GltfModel::noteDrops(const DropCounts& d) {
    if (d.degenerate) notes_.push_back(std::to_string(d.degenerate) + " degenerate triangles dropped");
    if (d.nonFinite) notes_.push_back(std::to_string(d.nonFinite) + " triangles with non-finite or out-of-bounds positions dropped");
    if (d.generated) notes_.push_back("normals generated for " + std::to_string(d.generated) + " primitives");
    if (d.unplaced) notes_.push_back(std::to_string(d.unplaced) + " primitives dropped: their node scales them to nothing or to infinity");
    if (skippedPointsLines_) notes_.push_back("points and lines are not rendered; skipped");
    if (weightsNormalized_)
        notes_.push_back(std::to_string(weightsNormalized_) + " skinned vertices have joint weights that do not sum to 1; normalized");
    if (weightsZero_) notes_.push_back(std::to_string(weightsZero_) + " skinned vertices have no joint weight; they follow their first joint");
    // Material extensions are noted per material, where they are met.
    for (const std::string& e : model_.extensionsUsed)
        if (!isSupportedExtension(e) && e.rfind("KHR_materials_", 0) != 0) notes_.push_back("extension " + e + " ignored");
}

void GltfModel::addTo(Scene& scene, const DMat4& worldFromModel, int materialOverride) {
    materialOverride_ = materialOverride;
    const DMat4 renderFromModel = glm::translate(DMat4(1.0), -scene.renderOrigin) * worldFromModel;
    const int modelIndex = int(scene.geometry.models.size());
    scene.geometry.models.push_back(sceneGraph(renderFromModel));

    // A node moves if it, or any ancestor, is animated (order_ lists parents first).
    std::vector<uint8_t> dynamic(model_.nodes.size(), 0);
    for (int i : order_) dynamic[size_t(i)] = animatedNode_[size_t(i)] || (parent_[size_t(i)] >= 0 && dynamic[size_t(parent_[size_t(i)])]);

    LoadStep step("building its meshes and materials");
    MaterialBuilder materials(scene, model_, path_, assets_);
    DropCounts dropped;
    for (int node : order_) {
        pollLoadCancel();
        const DMat4 renderFromNode = renderFromModel * modelFromNode_[size_t(node)];
        addNodeMeshes(scene, node, renderFromNode, modelIndex, dynamic[size_t(node)] != 0, materials, dropped);
        addNodeLightAndCamera(scene, node, renderFromNode);
    }
    noteDrops(dropped);
    for (const std::string& n : notes_) scene.notes.push_back(path_ + ": " + n);
}

}  // namespace

size_t loadGltfModel(Scene& scene, const std::string& path, const DMat4& worldFromModel, FileSource& fs, int materialOverride,
                     const AssetOptions& assets) {
    GltfModel model(path, fs, assets);
    model.addTo(scene, worldFromModel, materialOverride);
    return model.variantCount();
}

Scene loadGltfScene(const std::string& path, FileSource& fs, const SceneOptions& options) {
    Scene s;
    s.sourcePath = path;
    applyRenderSize(options, s.settings);
    GltfModel model(path, fs, options.assets);
    glm::dvec3 lo, hi;
    if (!model.bounds(DMat4(1.0), lo, hi)) throw InputError(path, model.emptyReason());
    if (options.inputsRead) {
        // The environment image is the one input still unread; read it now (it stays cached in
        // fs) so every file is in hand before the meshes, BVH and environment maps are built.
        if (options.environment && !options.environment->file.empty()) fs.read(options.environment->file, kMaxEnvironmentBytes);
        options.inputsRead();
    }
    const glm::dvec3 center = 0.5 * (lo + hi);
    s.renderOrigin = chooseRenderOrigin(center);
    model.addTo(s, DMat4(1.0));
    const float radius = float(0.5 * glm::length(hi - lo));
    const float aspect = float(s.settings.width) / float(s.settings.height);
    s.camera = frameBoundingSphere(Vec3(center - s.renderOrigin), radius > 0.f ? radius : 1.f, aspect);
    // A bare model (no lights of its own, no environment asked for) stands in the built-in
    // studio with one key light for crisp shadows; a model with its own lights gets a black
    // world, as Blender gives it. An environment given for a model without lights is its whole
    // light, as in Blender: a key light on top would light what the environment leaves in shade
    // (a backdrop facing away from the sky came out near white).
    SceneOptions opts = options;
    if (s.lights.empty() && !opts.environment) {
        addDefaultKeyLight(s, s.camera);
        opts.environment = EnvironmentSpec{};
    }
    s.background = Color(0.f);
    // glTF's light units are photometric and its models carry no exposure: meter one for the
    // film, and roll highlights off as the glTF Sample Viewer does.
    s.settings.autoExposure = true;
    s.settings.toneMap = ToneMap::PbrNeutral;
    // 2×2 stratified samples: at one, thin parallel edges (2CylinderEngine's fins) alias into a
    // moiré that crawls as the model turns. `rayfarm report` on that film put 4 spp at +6 dB
    // (31.4 → 37.5 dB against 64 spp) for 3.2× the time; 9 spp buys +5 dB more for 2.7× again.
    s.settings.spp = 4;
    attachEnvironment(s, std::nullopt, opts, fs);
    s.build();
    return s;
}

const Camera& chosenGltfCamera(const Scene& scene, int index) {
    if (index < 0 || size_t(index) >= scene.gltfCameras.size())
        throw InputError(scene.sourcePath, "no glTF camera " + std::to_string(index) + " (the scene has " +
                                               std::to_string(scene.gltfCameras.size()) + ")");
    // Named as the file names it: "model.gltf: cameras[2].perspective.yfov 0 is not ...".
    if (size_t(index) < scene.gltfCameraFaults.size() && !scene.gltfCameraFaults[size_t(index)].second.empty()) {
        const auto& [file, fault] = scene.gltfCameraFaults[size_t(index)];
        throw InputError(file, fault + "; choose another --camera");
    }
    return scene.gltfCameras[size_t(index)];
}

void useGltfCamera(Scene& scene, int index) { scene.camera = chosenGltfCamera(scene, index); }

}  // namespace rf
