#pragma once
/// A model's node hierarchy and keyframed animations, kept after loading so anim/ can move
/// nodes per frame. Engine fills it (glTF loader); anim evaluates it; Scene applies the result.
#include <string>
#include <utility>
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
    /// KHR_node_visibility's visible at rest (the node's own; a hidden node hides its subtree).
    bool visible = true;
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

/// What a KHR_animation_pointer channel sets besides a node's transform and morph weights
/// (those become AnimChannels): a property of a light, camera, material or texture transform,
/// or a node's KHR_node_visibility. Each takes the components its glTF type has.
enum class AnimProperty : uint8_t {
    // KHR_lights_punctual lights[target]
    LightColor, LightIntensity, LightRange, LightSpotInner, LightSpotOuter,
    // cameras[target]
    CameraYfov, CameraXmag, CameraYmag,
    // materials[target]
    BaseColor, Metallic, Roughness, Emissive, EmissiveStrength, AlphaCutoff, NormalScale, OcclusionStrength,
    Transmission, Ior, Thickness, AttenuationColor, AttenuationDistance, Clearcoat, ClearcoatRoughness,
    ClearcoatNormalScale, SheenColor, SheenRoughness, Specular, Iridescence, IridescenceIor, IridescenceThicknessMin,
    IridescenceThicknessMax,
    // materials[target]'s texture `slot` (TextureSlot), KHR_texture_transform
    TextureOffset, TextureRotation, TextureScale,
    // nodes[target]: KHR_node_visibility's visible (0 or 1, STEP)
    NodeVisible
};

/// The material textures a KHR_texture_transform pointer can name.
enum class TextureSlot : uint8_t {
    BaseColor, MetallicRoughness, Normal, Occlusion, Emissive, Clearcoat, ClearcoatRoughness, ClearcoatNormal,
    SheenColor, SheenRoughness, Thickness, Iridescence, IridescenceThickness, None
};

/// Components of a property's value (1 for scalars and booleans).
inline int propertyComponents(AnimProperty p) {
    switch (p) {
        case AnimProperty::LightColor:
        case AnimProperty::Emissive:
        case AnimProperty::AttenuationColor:
        case AnimProperty::SheenColor: return 3;
        case AnimProperty::BaseColor: return 4;
        case AnimProperty::TextureOffset:
        case AnimProperty::TextureScale: return 2;
        default: return 1;
    }
}

struct PropertyChannel {
    int sampler = 0;
    AnimProperty property = AnimProperty::LightIntensity;
    int target = 0;  ///< the file's light, camera, material or node index
    TextureSlot slot = TextureSlot::None;
};

struct Animation {
    std::string name;
    std::vector<AnimSampler> samplers;
    std::vector<AnimChannel> channels;
    std::vector<PropertyChannel> properties;  ///< KHR_animation_pointer targets beyond nodes
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

/// A material some animation's pointers change, and the file's values of what the engine keeps
/// as one product (emission = factor × strength; the volume's σ from colour and distance), so a
/// channel on one half combines with the other's.
struct AnimatedMaterial {
    int file = -1;   ///< materials[] of the file
    int scene = -1;  ///< Scene::materials (−1: nothing drawn uses it)
    Color emissiveFactor{0.f};
    float emissiveStrength = 1.f;
    Color attenuationColor{1.f};
    float attenuationDistance = 0.f;  ///< 0: infinite
};

/// One loaded model: its nodes, animations and where it sits in render space.
struct SceneGraph {
    std::string source;        ///< file it came from, for messages
    DMat4 renderFromModel{1.0};  ///< placement in the scene, rebased to Scene::renderOrigin
    std::vector<SceneNode> nodes;
    std::vector<Animation> animations;
    std::vector<Skin> skins;
    /// The materials that KHR_animation_pointer channels animate (AnimatedMaterial).
    std::vector<AnimatedMaterial> animatedMaterials;
    /// Lights on nodes hidden at rest that an animation can show (KHR_node_visibility): loaded
    /// with intensity 0, each with (its Scene::lights index, the intensity it gives when shown).
    std::vector<std::pair<int, float>> restHiddenLights;
};

}  // namespace rf
