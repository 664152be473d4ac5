#pragma once
/// The glTF loader's working model of one file (gltf_loader.cpp), internal to engine/load/gltf/:
/// gltf_model.cpp makes it and turns it into scene content; gltf_node_tree.cpp reads its node
/// hierarchy (transforms, skins, animations) and the scene graph animated nodes follow.
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/util/file_source.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_options.h"
#include "engine/load/gltf/gltf_geometry.h"
#include "engine/load/gltf/gltf_instancing.h"
#include "engine/load/gltf/gltf_materials.h"
#include "engine/load/gltf/gltf_parse.h"
#include "engine/load/gltf/gltf_variants.h"
#include "engine/geometry/skinning.h"

namespace rf::gltf {

/// A glTF file parsed and checked, with its node hierarchy resolved; turned into scene content
/// by addTo().
class GltfModel {
public:
    GltfModel(const std::string& path, FileSource& fs, const AssetOptions& assets);
    /// A model made in memory from another format (engine/load/assimp/), with the notes its
    /// import gathered; checked and resolved as a parsed file is.
    GltfModel(const std::string& path, tinygltf::Model model, std::vector<std::string> notes, const AssetOptions& assets);

    /// World-space bounds of the drawn triangles; false if there are none.
    bool bounds(const DMat4& worldFromModel, glm::dvec3& lo, glm::dvec3& hi);

    /// How many material variants the file names (KHR_materials_variants).
    size_t variantCount() const { return materialVariants(model_).size(); }

    /// materialOverride ≥ 0: every primitive in that scene material, the file's left unread.
    void addTo(Scene& scene, const DMat4& worldFromModel, int materialOverride = -1);

    /// After addTo, when nothing more will be read from the model: frees the file's buffers and
    /// images and the decoded primitives, so that building the scene's acceleration structure
    /// does not hold them as well (a big model's peak memory). bounds() and addTo() may not be
    /// called afterwards.
    void releaseLoadData();

    /// Why bounds() found nothing to draw, for the error message.
    std::string emptyReason() const;

private:
    void resolve();
    const PrimitiveGeometry* primitive(int mesh, int prim);

    /// Data a loader could silently work around, said once per primitive.
    void notePrimitive(const PrimitiveGeometry& g, const std::string& w);

    std::vector<double> defaultWeights(int node) const;

    DMat4 localTransform(int i) const;

    /// Whether primitive prim of node's mesh is drawn through the node's skin: the node has one
    /// and the primitive has JOINTS_n/WEIGHTS_n. Refuses joint indices the skin lacks.
    bool skinnedPrimitive(int node, const PrimitiveGeometry& g, int prim) const;

    /// A skinned primitive posed by its skin's rest joints (and the node's default morph
    /// weights), with its object-space copies kept.
    TriangleMesh restSkinned(int node, const PrimitiveGeometry& g, const DMat4& renderFromModel) const;

    /// skins[]: joints that are nodes, inverse bind matrices (MAT4 floats, one per joint, or
    /// the identity when absent), and the nodes that name them; the rest pose of every node
    /// (joints need not be in the drawn scene).
    void readSkins();

    void resolveHierarchy();

    /// Refuses models whose nodes instance more triangles than the cap, from accessor counts
    /// alone, before any geometry is built (nodes sharing a big mesh multiply it).
    void checkInstancedSize() const;

    void readAnimations();
    /// A KHR_animation_pointer channel's target (gltf_pointers.cpp): a node's translation,
    /// rotation, scale or weights (node ≥ 0, property), or another property rayfarm draws
    /// (target), else neither; pattern: the pointer with its indices as {} (what the note
    /// counts). Throws InputError on a pointer that is missing or malformed, that names an
    /// object the file lacks, or a property that object cannot have (a spot cone of a point
    /// light, the perspective of an orthographic camera, a transform of a texture the material lacks).
    struct AnimationPointer {
        int node = -1;
        std::string property;
        std::optional<PropertyChannel> target;
        std::string pattern, pointer;
    };
    AnimationPointer animationPointer(const tinygltf::AnimationChannel& ch, const std::string& where, int nodes) const;

    /// Primitives and triangles the load left out, summed over the model for its notes.
    struct DropCounts {
        size_t degenerate = 0, nonFinite = 0, generated = 0, unplaced = 0;
        size_t wires = 0;  ///< primitives of points or lines drawn
        size_t instancesUnplaced = 0;  ///< EXT_mesh_gpu_instancing instances of zero scale, per primitive
        size_t skinnedInstanced = 0;   ///< skinned primitives of instanced nodes, drawn once
    };
    SceneGraph sceneGraph(const DMat4& renderFromModel) const;
    void addNodeMeshes(Scene& scene, int node, const DMat4& renderFromNode, int modelIndex, bool dynamic,
                       MaterialBuilder& materials, DropCounts& dropped);
    /// withLight false: the node is hidden for good (KHR_node_visibility), only its camera counts.
    void addNodeLightAndCamera(Scene& scene, int node, const DMat4& renderFromNode, bool withLight = true);
    void noteDrops(const DropCounts& d);
    /// KHR_node_visibility's visible of the node itself (true when it has none).
    bool nodeVisible(int node) const;
    /// graph.animatedMaterials: each material a pointer animates, with its scene index and the
    /// file's values a channel combines with.
    void addAnimatedMaterials(SceneGraph& graph, const MaterialBuilder& materials) const;
    /// assets_.variant as an index into the file's variants (variant_), refused if it has none
    /// by that name; without a choice, a note lists the variants the file offers.
    void chooseMaterialVariant();
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
    std::vector<uint8_t> visibilityAnimated_;  ///< some channel animates the node's KHR_node_visibility
    /// EXT_mesh_gpu_instancing: each drawn node's instances, read after the size check; nodes
    /// without a mesh or without the extension are absent.
    std::map<int, std::vector<InstanceTrs>> gpuInstances_;
    void readGpuInstancing();
    std::vector<Animation> animations_;
    std::vector<Skin> skins_;
    std::vector<DMat4> restModelFromNode_;  ///< every node's rest transform (filled when there are skins)
    size_t weightsNormalized_ = 0, weightsZero_ = 0;
    int variant_ = -1;  ///< the chosen KHR_materials_variants variant, −1 for none
    std::map<std::pair<int, int>, std::optional<PrimitiveGeometry>> prims_;
    int materialOverride_ = -1;
    /// KHR_animation_pointer channels left out, by target pattern (noted once each).
    std::map<std::string, int> pointersIgnored_;
    /// The radius points and lines are drawn with, in world units (addTo sets it from the
    /// model's size and AssetOptions::pointSize); 0 before.
    double wireRadius_ = 0.0;
};

}  // namespace rf::gltf
