#include "anim/gltf_animation.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/util/errors.h"
#include "engine/geometry/skinning.h"

namespace rf::anim {

namespace {

KeyTrack samplerTrack(const AnimSampler& s, int dim, bool rotation) {
    if (dim < 1) throw std::invalid_argument("sampler has no components");
    const bool cubic = s.interpolation == KeyInterpolation::CubicSpline;
    const size_t per = static_cast<size_t>(dim) * (cubic ? 3 : 1);
    if (s.times.empty()) throw std::invalid_argument("sampler has no keys");
    if (s.values.size() != s.times.size() * per)
        throw std::invalid_argument("sampler output has " + std::to_string(s.values.size()) + " numbers, expected " +
                                    std::to_string(s.times.size() * per) + " for " + std::to_string(s.times.size()) +
                                    " keys");
    const Interp how = cubic ? Interp::Hermite : (s.interpolation == KeyInterpolation::Step ? Interp::Step : Interp::Linear);
    KeyTrack track(dim, rotation);
    std::vector<double> in(dim), v(dim), out(dim);
    for (size_t k = 0; k < s.times.size(); ++k) {
        const float* base = &s.values[k * per];
        for (int c = 0; c < dim; ++c) {
            if (cubic) {  // glTF layout per key: in-tangent, value, out-tangent
                in[c] = base[c];
                v[c] = base[dim + c];
                out[c] = base[2 * dim + c];
            } else {
                v[c] = base[c];
            }
        }
        track.addKey(double(s.times[k]), v.data(), how, cubic ? in.data() : nullptr, cubic ? out.data() : nullptr);
    }
    return track;
}

}  // namespace

KeyTrack trackFromSampler(const AnimSampler& s, AnimPath path) {
    const bool rotation = path == AnimPath::Rotation;
    return samplerTrack(s, path == AnimPath::Weights ? s.components : (rotation ? 4 : 3), rotation);
}

KeyTrack trackFromSampler(const AnimSampler& s, int components) { return samplerTrack(s, components, false); }

namespace {

/// Where a key's fault lies in the sampler's accessors: its time in input[k]; its value in
/// output[k], or with CUBICSPLINE (in-tangent, value, out-tangent per key) in output[3k + 0..2].
std::string samplerElement(const AnimSampler& s, const KeyError& e) {
    const long long k = e.key();
    if (e.field() == "time") return ".input[" + std::to_string(k) + "]";
    const bool cubic = s.interpolation == KeyInterpolation::CubicSpline;
    const long long at = !cubic ? k : 3 * k + (e.field() == "in" ? 0 : e.field() == "out" ? 2 : 1);
    return ".output[" + std::to_string(at) + "]";
}

}  // namespace

DMat4 nodeLocalMatrix(const SceneNode& n) {
    if (n.useMatrix) return n.matrix;
    DMat4 m = glm::translate(DMat4(1.0), n.translation);
    m = m * glm::mat4_cast(n.rotation);
    return glm::scale(m, n.scale);
}

std::vector<DMat4> modelFromNode(const SceneGraph& g, const std::vector<DMat4>& local) {
    const size_t n = g.nodes.size();
    std::vector<DMat4> world(n);
    std::vector<char> state(n, 0);  // 0 todo, 1 in progress (cycle guard), 2 done
    std::function<const DMat4&(size_t)> solve = [&](size_t i) -> const DMat4& {
        if (state[i] == 2) return world[i];
        const int p = g.nodes[i].parent;
        if (p >= 0 && static_cast<size_t>(p) < n && state[p] != 1) {
            state[i] = 1;
            world[i] = solve(static_cast<size_t>(p)) * local[i];
        } else {
            world[i] = local[i];
        }
        state[i] = 2;
        return world[i];
    };
    for (size_t i = 0; i < n; ++i) solve(i);
    return world;
}

GltfAnimationPlayer::GltfAnimationPlayer(const SceneGraph& g, int model, int animation, bool loop, double speed,
                                         double offset)
    : model_(model), speed_(speed), offset_(offset) {
    addAnimation(g, animation, loop);
}

GltfAnimationPlayer::GltfAnimationPlayer(const SceneGraph& g, int model, const std::vector<int>& animations, bool loop)
    : model_(model) {
    if (animations.empty()) throw InputError(g.source, "no animations to play");
    for (int a : animations) addAnimation(g, a, loop);
}

void GltfAnimationPlayer::addAnimation(const SceneGraph& g, int animation, bool loop) {
    if (animation < 0 || animation >= static_cast<int>(g.animations.size()))
        throw InputError(g.source, "no animation " + std::to_string(animation) + " (the model has " +
                                       std::to_string(g.animations.size()) + ")");
    const Animation& a = g.animations[animation];
    const std::string where = "animations[" + std::to_string(animation) + "]";
    const size_t part = parts_.size();
    Part p;
    p.animation = animation;
    p.loop = loop;
    for (size_t c = 0; c < a.channels.size(); ++c) {
        const AnimChannel& ch = a.channels[c];
        const std::string cw = where + ".channels[" + std::to_string(c) + "]";
        if (ch.node < 0 || ch.node >= static_cast<int>(g.nodes.size())) throw InputError(g.source, cw + ": no target node " + std::to_string(ch.node));
        if (ch.sampler < 0 || ch.sampler >= static_cast<int>(a.samplers.size()))
            throw InputError(g.source, cw + ": no sampler " + std::to_string(ch.sampler));
        if (g.nodes[ch.node].useMatrix && ch.path != AnimPath::Weights)
            throw InputError(g.source, cw + ": animates node " + std::to_string(ch.node) + ", which has a matrix (glTF allows only TRS on animated nodes)");
        const std::string sw = where + ".samplers[" + std::to_string(ch.sampler) + "]";
        try {
            channels_.push_back({ch.node, ch.path, trackFromSampler(a.samplers[ch.sampler], ch.path), part});
        } catch (const KeyError& e) {
            throw InputError(g.source, sw + samplerElement(a.samplers[ch.sampler], e) + ": " + e.what());
        } catch (const std::invalid_argument& e) {
            throw InputError(g.source, sw + ": " + e.what());
        }
        p.duration = std::max(p.duration, channels_.back().track.endTime());
    }
    for (size_t c = 0; c < a.properties.size(); ++c) {
        const PropertyChannel& pc = a.properties[c];
        const std::string sw = where + ".samplers[" + std::to_string(pc.sampler) + "]";
        if (pc.sampler < 0 || pc.sampler >= static_cast<int>(a.samplers.size()))
            throw InputError(g.source, where + ": a pointer channel has no sampler " + std::to_string(pc.sampler));
        try {
            properties_.push_back({pc, trackFromSampler(a.samplers[size_t(pc.sampler)], propertyComponents(pc.property)), part});
        } catch (const KeyError& e) {
            throw InputError(g.source, sw + samplerElement(a.samplers[size_t(pc.sampler)], e) + ": " + e.what());
        } catch (const std::invalid_argument& e) {
            throw InputError(g.source, sw + ": " + e.what());
        }
        p.duration = std::max(p.duration, properties_.back().track.endTime());
        anyVisibility_ |= pc.property == AnimProperty::NodeVisible;
    }
    // The nodes its channels move, and those below them (parents come first only by chance, so
    // walk up from each node).
    moving_.assign(g.nodes.size(), 0);
    std::vector<uint8_t> keyed(g.nodes.size(), 0);
    for (const Channel& c : channels_)
        if (c.path != AnimPath::Weights) keyed[size_t(c.node)] = 1;
    for (size_t i = 0; i < g.nodes.size(); ++i)
        for (int n = int(i), guard = 0; n >= 0 && size_t(n) < g.nodes.size() && guard <= int(g.nodes.size()); n = g.nodes[size_t(n)].parent, ++guard)
            if (keyed[size_t(n)]) {
                moving_[i] = 1;
                break;
            }
    for (const SceneNode& n : g.nodes) anyVisibility_ |= !n.visible;
    parts_.push_back(p);
    if (p.duration > duration_) {
        duration_ = p.duration;
        longest_ = part;
    }
}

std::vector<int> GltfAnimationPlayer::animations() const {
    std::vector<int> out;
    for (const Part& p : parts_) out.push_back(p.animation);
    return out;
}

double GltfAnimationPlayer::periodMoving(const SceneGraph& g, int node) const {
    std::vector<uint8_t> chain(g.nodes.size(), 0);  // node and the nodes above it
    for (int n = node, guard = 0; n >= 0 && size_t(n) < g.nodes.size() && guard < int(g.nodes.size()); n = g.nodes[size_t(n)].parent, ++guard)
        chain[size_t(n)] = 1;
    double p = 0.0;
    for (const Channel& c : channels_)
        if (c.path != AnimPath::Weights && size_t(c.node) < chain.size() && chain[size_t(c.node)]) p = std::max(p, partPeriod(c.part));
    return p;
}

void GltfAnimationPlayer::holdEndsAt(double seconds) {
    for (size_t i = 0; i < parts_.size(); ++i)
        if (partPeriod(i) >= seconds - 1e-9) parts_[i].loop = false;
}

double GltfAnimationPlayer::localTime(double t, size_t part) const {
    double a = t * speed_ + offset_;
    if (!std::isfinite(a)) return 0.0;
    const Part& p = parts_[part];
    if (p.loop && p.duration > 0.0) {
        a = std::fmod(a, p.duration);
        if (a < 0.0) a += p.duration;
    }
    return a;
}

void GltfAnimationPlayer::pose(const SceneGraph& g, double t, std::vector<DMat4>& renderFromNode,
                               std::vector<std::vector<double>>& weights) const {
    poseParts(g, [&](size_t part) { return localTime(t, part); }, renderFromNode, weights);
}

void GltfAnimationPlayer::poseLocal(const SceneGraph& g, double at, std::vector<DMat4>& renderFromNode,
                                    std::vector<std::vector<double>>& weights) const {
    poseParts(g, [at](size_t) { return at; }, renderFromNode, weights);
}

void GltfAnimationPlayer::poseParts(const SceneGraph& g, const std::function<double(size_t)>& timeOf,
                                    std::vector<DMat4>& renderFromNode, std::vector<std::vector<double>>& weights) const {
    std::vector<SceneNode> nodes = g.nodes;  // defaults, overridden by channels
    weights.assign(nodes.size(), {});
    for (size_t i = 0; i < nodes.size(); ++i) weights[i] = nodes[i].weights;
    std::vector<double> times(parts_.size());
    for (size_t i = 0; i < parts_.size(); ++i) times[i] = timeOf(i);
    for (const Channel& c : channels_) {
        SceneNode& n = nodes[c.node];
        const double at = times[c.part];
        switch (c.path) {
            case AnimPath::Translation: n.translation = c.track.evaluateVec3(at); break;
            case AnimPath::Rotation: n.rotation = c.track.evaluateQuat(at); break;
            case AnimPath::Scale: n.scale = c.track.evaluateVec3(at); break;
            case AnimPath::Weights:
                weights[c.node].assign(static_cast<size_t>(c.track.dim()), 0.0);
                c.track.evaluate(at, weights[c.node].data());
                break;
        }
    }
    std::vector<DMat4> local(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) local[i] = nodeLocalMatrix(nodes[i]);
    renderFromNode = modelFromNode(g, local);
    for (DMat4& m : renderFromNode) m = g.renderFromModel * m;
}

void GltfAnimationPlayer::apply(Scene& scene, double t) const {
    if (model_ < 0 || model_ >= static_cast<int>(scene.geometry.models.size())) return;
    std::vector<DMat4> renderFromNode;
    std::vector<std::vector<double>> weights;
    const SceneGraph& graph = scene.geometry.models[size_t(model_)];
    pose(graph, t, renderFromNode, weights);
    const auto timeOf = [&](size_t part) { return localTime(t, part); };
    std::vector<uint8_t> visible;
    if (anyVisibility_) visible = visibleNodes(graph, timeOf);
    applyLights(scene, renderFromNode, visible, timeOf);
    if (!properties_.empty()) applyMaterials(scene, timeOf);
    if (!visible.empty()) {
        // A hidden node's meshes collapse under a zero matrix (SceneGeometry leaves them out);
        // joints keep theirs, as a skin they move may hang on a node that is shown.
        std::vector<uint8_t> joint(renderFromNode.size(), 0);
        for (const Skin& sk : graph.skins)
            for (int j : sk.joints)
                if (j >= 0 && size_t(j) < joint.size()) joint[size_t(j)] = 1;
        for (size_t i = 0; i < renderFromNode.size(); ++i)
            if (!visible[i] && !joint[i]) renderFromNode[i] = DMat4(0.0);
    }
    bool loops = duration_ > 0.0;
    for (const Part& p : parts_) loops &= p.loop;
    if (!loops) {
        scene.geometry.applyNodeTransforms(model_, renderFromNode, weights);
        return;
    }
    // The nearest of kPoseAnchors poses spaced evenly over the looping clip (the longest one's
    // when several play, each of the others at the same share of its own duration): the one
    // whose tree a deforming mesh refits (SceneGeometry::PoseAnchor). Chosen from the local
    // time alone.
    const double phase = localTime(t) / duration_;
    SceneGeometry::PoseAnchor anchor;
    anchor.clip = parts_.size() == 1 ? parts_.front().animation : -1;  // -1: several together
    anchor.index = int(std::floor(phase * kPoseAnchors + 0.5)) % kPoseAnchors;
    const SceneGraph& g = graph;
    anchor.pose = [&, share = double(anchor.index) / kPoseAnchors](std::vector<DMat4>& n, std::vector<std::vector<double>>& w) {
        poseParts(g, [&](size_t part) { return parts_[part].duration * share; }, n, w);
    };
    scene.geometry.applyNodeTransforms(model_, renderFromNode, weights, &anchor);
}

std::vector<MeshExtent> meshExtents(const Scene& scene, int model) {
    std::vector<MeshExtent> out;
    for (size_t i = 0; i < scene.geometry.meshes.size(); ++i) {
        const TriangleMesh& m = scene.geometry.meshes[i];
        if (m.model != model || m.node < 0) continue;
        MeshExtent e;
        e.mesh = i;
        for (const Vec3& p : m.objectPositions) e.base.grow(p);
        for (const std::vector<Vec3>& target : m.morphPositions) {
            Aabb d;
            for (const Vec3& v : target) d.grow(v);
            e.morph.push_back(d);
        }
        if (m.skin >= 0 && m.influences > 0) {
            const SceneGraph& g = scene.geometry.models[size_t(model)];
            e.joints.resize(size_t(m.skin) < g.skins.size() ? g.skins[size_t(m.skin)].joints.size() : 0);
            for (size_t i = 0; i < m.objectPositions.size(); ++i)
                for (size_t k = i * size_t(m.influences); k < (i + 1) * size_t(m.influences); ++k)
                    if (m.skinWeights[k] > 0.f && m.skinJoints[k] < e.joints.size()) e.joints[m.skinJoints[k]].grow(m.objectPositions[i]);
        }
        out.push_back(std::move(e));
    }
    return out;
}

void GltfAnimationPlayer::growPosedBounds(const Scene& scene, double t, const std::vector<MeshExtent>& extents, Aabb& b) const {
    visitPosed(scene, t, extents, [&](const Vec3& q) { b.grow(q); });
}

void GltfAnimationPlayer::visitPosed(const Scene& scene, double t, const std::vector<MeshExtent>& extents,
                                     const std::function<void(const Vec3&)>& visit) const {
    if (model_ < 0 || model_ >= static_cast<int>(scene.geometry.models.size())) return;
    std::vector<DMat4> renderFromNode;
    std::vector<std::vector<double>> weights;
    pose(scene.geometry.models[model_], t, renderFromNode, weights);
    const SceneGraph& graph = scene.geometry.models[size_t(model_)];
    std::vector<std::vector<DMat4>> joints(graph.skins.size());
    for (const MeshExtent& e : extents) {
        const TriangleMesh& mesh = scene.geometry.meshes[e.mesh];
        if (mesh.model != model_ || mesh.node < 0 || mesh.node >= static_cast<int>(renderFromNode.size()) || e.base.empty()) continue;
        const bool skinned = mesh.skin >= 0 && size_t(mesh.skin) < joints.size();
        if (skinned && joints[size_t(mesh.skin)].empty()) joints[size_t(mesh.skin)] = jointMatrices(graph.skins[size_t(mesh.skin)], renderFromNode);
        const DMat4& m = renderFromNode[mesh.node];
        const std::vector<double>& w = weights[mesh.node];
        auto grow = [&](const DMat4& by, const DVec3& p) {
            const Vec3 q(DVec3(by * glm::dvec4(p, 1.0)));
            if (isFinite(q)) visit(q);
        };
        if (mesh.objectPositions.size() <= kExactBoundsVertices) {
            for (size_t i = 0; i < mesh.objectPositions.size(); ++i) {
                DVec3 p(mesh.objectPositions[i]);
                for (size_t k = 0; k < w.size() && k < mesh.morphPositions.size(); ++k)
                    if (!mesh.morphPositions[k].empty()) p += w[k] * DVec3(mesh.morphPositions[k][i]);
                grow(skinned ? skinMatrix(mesh, i, joints[size_t(mesh.skin)]) : m, p);
            }
            continue;
        }
        // Box of base + Σ w·delta: each target adds w·[lo, hi] (ends swapped for negative w).
        DVec3 lo(0.0), hi(0.0);
        for (size_t k = 0; k < w.size() && k < e.morph.size(); ++k) {
            if (e.morph[k].empty()) continue;
            const DVec3 a = w[k] * DVec3(e.morph[k].lo), c = w[k] * DVec3(e.morph[k].hi);
            lo += glm::min(a, c);
            hi += glm::max(a, c);
        }
        auto corners = [&](const DMat4& by, const Aabb& box) {
            const DVec3 l = DVec3(box.lo) + lo, h = DVec3(box.hi) + hi;
            for (int corner = 0; corner < 8; ++corner) grow(by, DVec3(corner & 1 ? h.x : l.x, corner & 2 ? h.y : l.y, corner & 4 ? h.z : l.z));
        };
        if (!skinned) {
            corners(m, e.base);
            continue;
        }
        for (size_t j = 0; j < e.joints.size(); ++j)
            if (!e.joints[j].empty()) corners(joints[size_t(mesh.skin)][j], e.joints[j]);
    }
}

namespace {
bool isIndex(const std::string& s) { return !s.empty() && s.size() < 10 && s.find_first_not_of("0123456789") == std::string::npos; }
}  // namespace

std::vector<int> animationsMoving(const SceneGraph& g, int node) {
    std::vector<uint8_t> chain(g.nodes.size(), 0);
    for (int n = node, guard = 0; n >= 0 && size_t(n) < g.nodes.size() && guard < int(g.nodes.size()); n = g.nodes[size_t(n)].parent, ++guard)
        chain[size_t(n)] = 1;
    std::vector<int> out;
    for (size_t a = 0; a < g.animations.size(); ++a)
        for (const AnimChannel& c : g.animations[a].channels)
            if (c.path != AnimPath::Weights && c.node >= 0 && size_t(c.node) < chain.size() && chain[size_t(c.node)]) {
                out.push_back(int(a));
                break;
            }
    return out;
}

std::vector<int> animationsKeyingLens(const SceneGraph& g, int camera) {
    std::vector<int> out;
    for (size_t a = 0; a < g.animations.size(); ++a)
        for (const PropertyChannel& c : g.animations[a].properties)
            if (c.target == camera && (c.property == AnimProperty::CameraYfov || c.property == AnimProperty::CameraXmag ||
                                       c.property == AnimProperty::CameraYmag)) {
                out.push_back(int(a));
                break;
            }
    return out;
}

std::vector<int> defaultAnimations(const SceneGraph& g) {
    std::vector<int> chosen;
    // (node, path) pairs taken; weights count as a path of their own.
    std::vector<uint8_t> taken(g.nodes.size() * 4, 0);
    // KHR_animation_pointer properties taken: (property, target, texture slot).
    std::set<std::tuple<int, int, int>> takenProperties;
    auto key = [](const PropertyChannel& c) { return std::make_tuple(int(c.property), c.target, int(c.slot)); };
    for (size_t a = 0; a < g.animations.size(); ++a) {
        const Animation& an = g.animations[a];
        bool clash = false;
        for (const AnimChannel& c : an.channels)
            if (c.node >= 0 && size_t(c.node) < g.nodes.size() && taken[size_t(c.node) * 4 + size_t(c.path)]) clash = true;
        for (const PropertyChannel& c : an.properties) clash |= takenProperties.count(key(c)) != 0;
        if (clash) continue;
        for (const AnimChannel& c : an.channels)
            if (c.node >= 0 && size_t(c.node) < g.nodes.size()) taken[size_t(c.node) * 4 + size_t(c.path)] = 1;
        for (const PropertyChannel& c : an.properties) takenProperties.insert(key(c));
        chosen.push_back(int(a));
    }
    if (chosen.empty() && !g.animations.empty()) chosen.push_back(0);
    return chosen;
}

int chooseAnimation(const SceneGraph& g, const std::string& choice) {
    const int byName = findAnimation(g, choice);
    if (byName >= 0) return byName;
    if (isIndex(choice) && std::stoi(choice) < static_cast<int>(g.animations.size())) return std::stoi(choice);
    return -1;
}

std::string missingAnimation(const SceneGraph& g, const std::string& choice) {
    const std::string file = std::filesystem::path(g.source).filename().string();
    // Built by appends: GCC 12's inlining of operator+ chains warns falsely under LTO.
    std::string msg = "no animation ";
    if (isIndex(choice)) {
        msg += choice;
    } else {
        msg += "named \"";
        msg += choice;
        msg += '"';
    }
    msg += " (";
    msg += file;
    if (g.animations.empty()) {
        msg += " has no animations";
    } else {
        msg += " has ";
        msg += std::to_string(g.animations.size());
        msg += ": ";
        for (size_t i = 0; i < g.animations.size(); ++i) {
            if (i) msg += ", ";
            msg += std::to_string(i);
            msg += " \"";
            msg += g.animations[i].name;
            msg += '"';
        }
    }
    msg += ')';
    return msg;
}

double filmSecondsForClip(double clip, double orbit) {
    if (!(clip > 0.0) || !(clip <= 3600.0)) return orbit;  // no clip, or one longer than any film
    const double plays = std::max(1.0, std::ceil(orbit / clip - 1e-9));
    return plays * clip;
}

int findAnimation(const SceneGraph& g, const std::string& name) {
    for (size_t i = 0; i < g.animations.size(); ++i)
        if (g.animations[i].name == name) return static_cast<int>(i);
    return -1;
}

}  // namespace rf::anim
