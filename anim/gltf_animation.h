#pragma once
/// Plays a model's own glTF animation: samplers evaluated with the glTF rules (LINEAR with slerp
/// for rotations, STEP, CUBICSPLINE with tangents scaled by the key interval), node TRS and
/// morph weights, node world matrices, and the meshes moved through SceneGeometry::applyNodeTransforms.
#include <functional>
#include <string>
#include <vector>

#include "anim/keyframes.h"
#include "engine/scene/scene.h"

namespace rf::anim {

/// A glTF sampler as a key track (CUBICSPLINE becomes Hermite with its in/out tangents; the
/// per-second tangents are scaled by the key interval on evaluation). Throws KeyError for times
/// that do not increase; std::invalid_argument if the value count does not match the keys.
KeyTrack trackFromSampler(const AnimSampler& sampler, AnimPath path);
/// The same for a KHR_animation_pointer property of `components` numbers (never a rotation).
KeyTrack trackFromSampler(const AnimSampler& sampler, int components);

/// Local transform of a node from its TRS (or matrix).
DMat4 nodeLocalMatrix(const SceneNode& node);

/// Model-from-node matrices of every node, parents first, from local matrices.
std::vector<DMat4> modelFromNode(const SceneGraph& graph, const std::vector<DMat4>& local);

/// Object-space box of an animated mesh and of each morph target's deltas; for a skinned
/// mesh also, per joint, the bind-space box of the vertices that joint moves.
struct MeshExtent {
    size_t mesh = 0;
    Aabb base;
    std::vector<Aabb> morph;
    std::vector<Aabb> joints;
};

/// Extents of every animated mesh (node ≥ 0) of scene.geometry.models[model].
std::vector<MeshExtent> meshExtents(const Scene& scene, int model);

/// One animation of one model, or several played together (--animation all), ready to evaluate
/// at any time.
class GltfAnimationPlayer {
public:
    /// Compiles graph.animations[animation]. Throws InputError naming graph.source and the
    /// sampler on invalid keys or channel targets.
    GltfAnimationPlayer(const SceneGraph& graph, int model, int animation, bool loop, double speed = 1.0,
                        double offset = 0.0);
    /// Several of the model's animations played together, each looped (or not) over its own
    /// duration; where two animate the same node property, the later one in `animations` wins.
    GltfAnimationPlayer(const SceneGraph& graph, int model, const std::vector<int>& animations, bool loop);

    int model() const { return model_; }
    /// The first (for one animation: the only) animation it plays.
    int animation() const { return parts_.front().animation; }
    /// The animations it plays, in order.
    std::vector<int> animations() const;
    /// Seconds of timeline time one play of animation part `i` (of animations()) takes.
    double partPeriod(size_t i) const { return speed_ != 0.0 ? parts_[i].duration / std::abs(speed_) : 0.0; }
    double duration() const { return duration_; }
    /// Seconds of timeline time one play of the clip takes (duration / |speed|; 0: no motion).
    /// Several animations: the longest of them.
    double period() const { return speed_ != 0.0 ? duration_ / std::abs(speed_) : 0.0; }
    /// The longest period of the animations it plays that move `node` of graph or a node above
    /// it (translation, rotation or scale); 0 when none does.
    double periodMoving(const SceneGraph& graph, int node) const;
    /// Plays the animations whose period is `seconds` or more once and holds their last pose
    /// instead of looping: a film of that length then ends on their last key, not their first.
    void holdEndsAt(double seconds);
    /// Animation-local time for timeline time t: (t·speed + offset), wrapped into [0, duration)
    /// when looping, else clamped by the samplers. Several animations: the longest one's.
    double localTime(double t) const { return localTime(t, longest_); }
    /// Render-from-node matrices and morph weights of every node at timeline time t.
    void pose(const SceneGraph& graph, double t, std::vector<DMat4>& renderFromNode,
              std::vector<std::vector<double>>& weights) const;
    /// The same at animation-local time `at` (no looping or speed applied).
    void poseLocal(const SceneGraph& graph, double at, std::vector<DMat4>& renderFromNode,
                   std::vector<std::vector<double>>& weights) const;
    /// Poses the model at t and moves its meshes (re-transform and BVH refit). A looping clip
    /// names the nearest of kPoseAnchors poses spaced over it, whose tree a deforming mesh's
    /// is refitted from (SceneGeometry::PoseAnchor).
    /// KHR_animation_pointer properties are set too: the model's lights (their node's motion,
    /// colour, intensity, range and cones; a light whose node is hidden gives no light), its
    /// materials (factors and texture transforms) and its nodes' KHR_node_visibility (a hidden
    /// node's meshes are posed with a zero matrix, which SceneGeometry leaves out of the frame).
    /// It sets only what the animations key, on top of the lights as the caller has them:
    /// Timeline::apply resets them to their loaded values first, so that a frame depends on its
    /// time alone.
    void apply(Scene& scene, double t) const;
    /// Sets the properties of the file's camera `camera` (its cameras[] index) that the
    /// animations key (yfov; xmag or ymag, whichever the lens is fitted by) at timeline time t.
    void applyCamera(int camera, double t, Camera& lens) const;
    /// Whether some animation it plays keys a property of the file's camera `camera`.
    bool animatesCamera(int camera) const;
    static constexpr int kPoseAnchors = 8;
    /// Grows b (render space) by the model's animated meshes as posed at t, leaving the scene
    /// untouched: for framing a film on where the model goes, not only where it rests. Meshes
    /// above kExactBoundsVertices are bounded by their transformed object-space box (looser,
    /// but O(1) per pose instead of O(vertices)); a skinned one above it by its joints' boxes,
    /// each through its joint matrix (a blended vertex lies in their hull).
    void growPosedBounds(const Scene& scene, double t, const std::vector<MeshExtent>& extents, Aabb& b) const;
    /// The points growPosedBounds grows b by (the posed vertices, or the corners of the boxes
    /// that stand for them), each passed to visit.
    void visitPosed(const Scene& scene, double t, const std::vector<MeshExtent>& extents,
                    const std::function<void(const Vec3&)>& visit) const;
    static constexpr size_t kExactBoundsVertices = 4096;

private:
    struct Channel {
        int node;
        AnimPath path;
        KeyTrack track;
        size_t part;  ///< which of parts_ it belongs to
    };
    /// A KHR_animation_pointer property's keys.
    struct PropertyTrack {
        PropertyChannel target;
        KeyTrack track;
        size_t part;
    };
    struct Part {
        int animation = 0;
        double duration = 0.0;
        bool loop = true;
    };
    void addAnimation(const SceneGraph& graph, int animation, bool loop);
    double localTime(double t, size_t part) const;
    /// Poses every node with each part at the time timeOf(part) gives.
    void poseParts(const SceneGraph& graph, const std::function<double(size_t)>& timeOf, std::vector<DMat4>& renderFromNode,
                   std::vector<std::vector<double>>& weights) const;
    int model_ = 0;
    size_t longest_ = 0;  ///< the part with the longest duration
    double speed_ = 1.0, offset_ = 0.0;
    double duration_ = 0.0;
    std::vector<Part> parts_;
    std::vector<Channel> channels_;
    std::vector<PropertyTrack> properties_;
    /// Nodes a channel of it moves (translation, rotation, scale), or below one.
    std::vector<uint8_t> moving_;
    bool anyVisibility_ = false;  ///< some node's visibility is keyed, or some node is hidden at rest
    /// Each node's visibility (its own and its parents') at the parts' times.
    std::vector<uint8_t> visibleNodes(const SceneGraph& graph, const std::function<double(size_t)>& timeOf) const;
    void applyLights(Scene& scene, const std::vector<DMat4>& renderFromNode, const std::vector<uint8_t>& visible,
                     const std::function<double(size_t)>& timeOf) const;
    void applyMaterials(Scene& scene, const std::function<double(size_t)>& timeOf) const;
};

/// The choice that plays every animation of a model together (--animation all).
inline constexpr const char* kAllAnimations = "all";

/// Index of the animation called `name` in graph, or -1.
int findAnimation(const SceneGraph& graph, const std::string& name);

/// The animation `choice` names in graph: a name, else a decimal index; -1 if none.
int chooseAnimation(const SceneGraph& graph, const std::string& choice);
/// The animations of graph that move `node` or a node above it (translation, rotation, scale).
std::vector<int> animationsMoving(const SceneGraph& graph, int node);
/// The animations of graph that key a lens property of the file's camera `camera` (its cameras[]
/// index) through KHR_animation_pointer: yfov, xmag, ymag.
std::vector<int> animationsKeyingLens(const SceneGraph& graph, int camera);

/// What a bare model plays when nothing is chosen: its animations in order, each one taken
/// unless it animates a node property (translation, rotation, scale, morph weights), or a property
/// through KHR_animation_pointer, that an animation already taken animates.
/// Blender's one animation per object (or NLA track) all play together; alternative takes of
/// one rig (Fox's Survey, Walk, Run) leave only the first.
std::vector<int> defaultAnimations(const SceneGraph& graph);
/// Why chooseAnimation found nothing, listing what the file has: `no animation named "Run"
/// (model.gltf has 2: 0 "Idle", 1 "Walk")`.
std::string missingAnimation(const SceneGraph& graph, const std::string& choice);

/// A bare model's film length when it plays a clip of `clipSeconds`: the smallest whole number
/// of plays that lasts at least `orbitSeconds` (the default orbit), so that both the clip and the
/// one orbit over the film loop seamlessly. Without a clip (≤ 0, or over an hour): orbitSeconds.
double filmSecondsForClip(double clipSeconds, double orbitSeconds);

}  // namespace rf::anim
