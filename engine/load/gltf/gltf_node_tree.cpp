// GltfModel's node hierarchy: each node's transform, the tree resolved and checked, the skins
// with every node's rest pose, the animations, and the scene graph animated nodes follow.
#include "engine/load/gltf/gltf_model.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/load/gltf/gltf_accessors.h"
#include "engine/load/gltf/gltf_instancing.h"
#include "engine/load/gltf/gltf_safety.h"

namespace rf::gltf {

namespace {

bool finiteMat(const DMat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

}  // namespace

std::vector<double> GltfModel::defaultWeights(int node) const {
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    if (!n.weights.empty()) return n.weights;
    return n.mesh >= 0 ? model_.meshes[size_t(n.mesh)].weights : std::vector<double>{};
}

DMat4 GltfModel::localTransform(int i) const {
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

bool GltfModel::skinnedPrimitive(int node, const PrimitiveGeometry& g, int prim) const {
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

TriangleMesh GltfModel::restSkinned(int node, const PrimitiveGeometry& g, const DMat4& renderFromModel) const {
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

void GltfModel::readSkins() {
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

void GltfModel::resolveHierarchy() {
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
    int sceneIndex = model_.defaultScene >= 0 ? model_.defaultScene : model_.scenes.empty() ? -1 : 0;
    if (assets_.scene >= 0) {
        if (size_t(assets_.scene) >= model_.scenes.size())
            throw InputError(path_, assets_.sceneSource + ": no scene " + std::to_string(assets_.scene) + " (the file has " +
                                        std::to_string(model_.scenes.size()) + (model_.scenes.size() == 1 ? " scene)" : " scenes)"));
        sceneIndex = assets_.scene;
    }
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

void GltfModel::checkInstancedSize() const {
    const uint64_t cap = Limits::kMaxTriangles;
    uint64_t corners = 0;  // three per triangle drawn, an upper bound
    for (int node : order_) {
        const int mesh = model_.nodes[size_t(node)].mesh;
        if (mesh < 0) continue;
        // EXT_mesh_gpu_instancing writes the vertices out once per instance as well.
        const uint64_t instances = gpuInstanceCount(model_, node);
        for (const tinygltf::Primitive& p : model_.meshes[size_t(mesh)].primitives) {
            auto count = [&](int acc) { return acc >= 0 && size_t(acc) < model_.accessors.size() ? uint64_t(model_.accessors[size_t(acc)].count) : 0; };
            const auto pos = p.attributes.find("POSITION");
            const uint64_t vertices = pos == p.attributes.end() ? 0 : count(pos->second);
            uint64_t n = p.indices >= 0 ? count(p.indices) : vertices;
            // Points become 8 triangles each and line segments 12 (wireGeometry): 24 and 36
            // corners an element at most; strips and fans at most one triangle an element.
            if (p.mode == TINYGLTF_MODE_POINTS) n *= 24;
            else if (p.mode >= TINYGLTF_MODE_LINE && p.mode <= TINYGLTF_MODE_LINE_STRIP) n *= 36;
            else if (p.mode == TINYGLTF_MODE_TRIANGLE_STRIP || p.mode == TINYGLTF_MODE_TRIANGLE_FAN) n *= 3;
            if (instances != 1) n = std::max({n, vertices, uint64_t(1)});  // each instance costs something
            // Each factor is at most 36 · 2^26 and the sum stops past the cap: no overflow.
            corners += std::min(n, 3 * cap + 1) * std::min(instances, 3 * cap + 1);
            if (corners / 3 > cap)
                throw InputError(path_, "over " + std::to_string(cap) + " triangles once nodes instance their meshes (the limit)");
        }
    }
}

void GltfModel::readAnimations() {
    animatedNode_.assign(model_.nodes.size(), 0);
    visibilityAnimated_.assign(model_.nodes.size(), 0);
    for (size_t a = 0; a < model_.animations.size(); ++a) {
        const tinygltf::Animation& ga = model_.animations[a];
        const std::string wa = "animations[" + std::to_string(a) + "]";
        Animation anim;
        anim.name = ga.name;
        // Sampler components depend on the channel's path; find them first.
        std::vector<int> comps(ga.samplers.size(), 0);
        std::vector<uint8_t> pointerOnly(ga.samplers.size(), 0);  // read by pointers left out
        // Samplers of property pointers: the accessor type their property needs (0: none), and
        // the pointer, for the refusal.
        std::vector<int> propertyType(ga.samplers.size(), 0);
        std::vector<uint8_t> boolean(ga.samplers.size(), 0);
        std::vector<std::string> propertyPointer(ga.samplers.size());
        for (size_t c = 0; c < ga.channels.size(); ++c) {
            const tinygltf::AnimationChannel& ch = ga.channels[c];
            const std::string wc = wa + ".channels[" + std::to_string(c) + "]";
            if (ch.sampler < 0 || size_t(ch.sampler) >= ga.samplers.size()) throw InputError(path_, wc + ".sampler: no such sampler");
            int node = ch.target_node;
            std::string property = ch.target_path;
            if (ch.target_path == "pointer") {
                // KHR_animation_pointer: a node's TRS or weights become the channel they name;
                // any other target is left out with a note (its sampler is not read).
                const AnimationPointer ptr = animationPointer(ch, wc, int(model_.nodes.size()));
                if (ptr.target) {
                    // A light, camera, material, texture-transform or visibility property.
                    const size_t s = size_t(ch.sampler);
                    const int k = propertyComponents(ptr.target->property);
                    propertyType[s] = k == 1 ? TINYGLTF_TYPE_SCALAR : k == 2 ? TINYGLTF_TYPE_VEC2 : k == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
                    boolean[s] = ptr.target->property == AnimProperty::NodeVisible;
                    propertyPointer[s] = ptr.pointer;
                    comps[s] = k;
                    anim.properties.push_back(*ptr.target);
                    if (ptr.target->property == AnimProperty::NodeVisible)
                        animatedNode_[size_t(ptr.target->target)] = visibilityAnimated_[size_t(ptr.target->target)] = 1;
                    continue;
                }
                if (ptr.node < 0) {
                    ++pointersIgnored_[ptr.pattern];
                    pointerOnly[size_t(ch.sampler)] = 1;
                    continue;
                }
                node = ptr.node;
                property = ptr.property;
            } else if (node < 0) {
                continue;  // targets something else (an extension's): nothing to move
            }
            if (size_t(node) >= model_.nodes.size()) throw InputError(path_, wc + ".target.node: no such node");
            AnimChannel out;
            out.sampler = ch.sampler;
            out.node = node;
            int k = 0;
            if (property == "translation") out.path = AnimPath::Translation, k = 3;
            else if (property == "rotation") out.path = AnimPath::Rotation, k = 4;
            else if (property == "scale") out.path = AnimPath::Scale, k = 3;
            else if (property == "weights") out.path = AnimPath::Weights, k = -1;
            else throw InputError(path_, wc + ".target.path: \"" + ch.target_path + "\" is not a glTF path");
            comps[size_t(ch.sampler)] = k;
            anim.channels.push_back(out);
            animatedNode_[size_t(node)] = 1;
        }
        for (size_t s = 0; s < ga.samplers.size(); ++s) {
            const tinygltf::AnimationSampler& gs = ga.samplers[s];
            const std::string ws = wa + ".samplers[" + std::to_string(s) + "]";
            AnimSampler out;
            if (pointerOnly[s] && comps[s] == 0) {
                // Only pointers rayfarm does not follow read it: its keys may be of any type
                // (VEC2 offsets, booleans), and nothing plays them. A keyless placeholder.
                out.components = 1;
                anim.samplers.push_back(std::move(out));
                continue;
            }
            if (gs.interpolation == "STEP") out.interpolation = KeyInterpolation::Step;
            else if (gs.interpolation == "CUBICSPLINE") out.interpolation = KeyInterpolation::CubicSpline;
            else out.interpolation = KeyInterpolation::Linear;
            const AccessorData in = readAccessor(model_, gs.input, path_, {TINYGLTF_TYPE_SCALAR});
            if (propertyType[s]) {
                // The output accessor must be of the property's type (booleans: unsigned bytes, STEP).
                const tinygltf::Accessor* acc =
                    gs.output >= 0 && size_t(gs.output) < model_.accessors.size() ? &model_.accessors[size_t(gs.output)] : nullptr;
                const char* need = propertyType[s] == TINYGLTF_TYPE_SCALAR ? "SCALAR" : propertyType[s] == TINYGLTF_TYPE_VEC2 ? "VEC2"
                                   : propertyType[s] == TINYGLTF_TYPE_VEC3                                               ? "VEC3"
                                                                                                                         : "VEC4";
                const std::string what = ws + ".output: accessors[" + std::to_string(gs.output) + "] ";
                if (acc && acc->type != propertyType[s])
                    throw InputError(path_, what + "is not " + need + ", as the pointer \"" + propertyPointer[s] + "\" needs");
                if (acc && boolean[s] && (acc->componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || gs.interpolation != "STEP"))
                    throw InputError(path_, what + "animates the boolean \"" + propertyPointer[s] +
                                                "\": it must hold unsigned bytes, played with STEP interpolation");
            }
            const AccessorData val = readAccessor(model_, gs.output, path_,
                                                  propertyType[s] ? std::vector<int>{propertyType[s]}
                                                                  : std::vector<int>{TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});
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
        sn.visible = nodeVisible(int(i));
        graph.nodes.push_back(std::move(sn));
    }
    graph.animations = animations_;
    graph.skins = skins_;
    return graph;
}

}  // namespace rf::gltf
