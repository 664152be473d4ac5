#pragma once
/// A model's node hierarchy and keyframed animations, kept after loading so anim/ can move
/// nodes per frame. Engine fills it (glTF loader); anim evaluates it; Scene applies the result.
#include <string>
#include <vector>

#include "engine/util/vec_math.h"

namespace rf {

struct SceneNode {
    std::string name;
    int parent = -1;
    DVec3 translation{0.0};
    DQuat rotation{1.0, 0.0, 0.0, 0.0};  ///< glm order (w, x, y, z)
    DVec3 scale{1.0};
    bool useMatrix = false;  ///< the node gave a matrix instead of TRS
    DMat4 matrix{1.0};
    std::vector<double> weights;  ///< default morph weights of the node's mesh
};

enum class KeyInterpolation { Linear, Step, CubicSpline };
enum class AnimPath { Translation, Rotation, Scale, Weights };

struct AnimSampler {
    std::vector<float> times;   ///< strictly increasing, seconds
    std::vector<float> values;  ///< components per key (×3 for CUBICSPLINE: in, value, out)
    int components = 3;
    KeyInterpolation interpolation = KeyInterpolation::Linear;
};

struct AnimChannel {
    int sampler = 0;
    int node = 0;
    AnimPath path = AnimPath::Translation;
};

struct Animation {
    std::string name;
    std::vector<AnimSampler> samplers;
    std::vector<AnimChannel> channels;
    float duration() const {
        float d = 0.f;
        for (const auto& s : samplers)
            if (!s.times.empty()) d = std::max(d, s.times.back());
        return d;
    }
};

/// A glTF skin: the joint nodes and, per joint, the matrix from the mesh's bind space into the
/// joint's space (identity when the file gives none).
struct Skin {
    std::string name;
    std::vector<int> joints;          ///< node indices
    std::vector<DMat4> inverseBind;   ///< one per joint
};

/// One loaded model: its nodes, animations and where it sits in render space.
struct SceneGraph {
    std::string source;        ///< file it came from, for messages
    DMat4 renderFromModel{1.0};  ///< placement in the scene, rebased to Scene::renderOrigin
    std::vector<SceneNode> nodes;
    std::vector<Animation> animations;
    std::vector<Skin> skins;
};

}  // namespace rf
