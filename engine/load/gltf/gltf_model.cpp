#include "engine/load/gltf/gltf_model.h"

#include <cstdio>
#include <set>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/geometry/skinning.h"
#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/load/gltf/gltf_instancing.h"
#include "engine/load/gltf/gltf_lights_cameras.h"
#include "engine/load/gltf/gltf_safety.h"
#include "engine/load/gltf/gltf_variants.h"

namespace rf::gltf {

namespace {
constexpr double kWireDiagonalPixels = 480.0;  ///< see addTo
/// A length as a note shows it: three significant digits.
std::string formatted(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}
}  // namespace

GltfModel::GltfModel(const std::string& path, FileSource& fs, const AssetOptions& assets) : path_(path), assets_(assets) {
    model_ = parseGltf(path, fs, assets, notes_);
    resolve();
}

GltfModel::GltfModel(const std::string& path, tinygltf::Model model, std::vector<std::string> notes, const AssetOptions& assets)
    : path_(path), assets_(assets), model_(std::move(model)), notes_(std::move(notes)) {
    resolve();
}

void GltfModel::readGpuInstancing() {
    for (int node : order_) {
        if (model_.nodes[size_t(node)].mesh < 0) continue;  // the extension places a node's mesh
        GpuInstances g = readGpuInstances(model_, node, path_);
        if (g.present) gpuInstances_[node] = std::move(g.instances);
    }
}

void GltfModel::resolve() {
    pollLoadCancel();
    LoadStep resolving("resolving its node hierarchy");
    chooseMaterialVariant();
    resolveHierarchy();
    checkInstancedSize();
    readGpuInstancing();
    readAnimations();
    readSkins();
}

bool GltfModel::bounds(const DMat4& worldFromModel, glm::dvec3& lo, glm::dvec3& hi) {
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
            // Each instance's corners of the primitive's box in its own space (instances are
            // many and small, so the box of the boxes), or each vertex without instancing.
            auto it = skinned ? gpuInstances_.end() : gpuInstances_.find(node);
            const std::vector<uint32_t>& used = g->wire ? g->wirePoints : g->mesh.indices;
            if (it != gpuInstances_.end()) {
                glm::dvec3 plo(std::numeric_limits<double>::infinity()), phi = -plo;
                for (uint32_t i : used) plo = glm::min(plo, glm::dvec3(pos[i])), phi = glm::max(phi, glm::dvec3(pos[i]));
                if (used.empty()) continue;
                for (const InstanceTrs& inst : it->second) {
                    const DMat4 placed = m * inst.matrix();
                    for (int c = 0; c < 8; ++c) {
                        const glm::dvec3 corner(c & 1 ? phi.x : plo.x, c & 2 ? phi.y : plo.y, c & 4 ? phi.z : plo.z);
                        const glm::dvec3 q(placed * glm::dvec4(corner, 1.0));
                        lo = glm::min(lo, q);
                        hi = glm::max(hi, q);
                        any = true;
                    }
                }
                continue;
            }
            for (uint32_t i : used) {
                const glm::dvec3 q = skinned ? glm::dvec3(pos[i]) : glm::dvec3(m * glm::dvec4(glm::dvec3(pos[i]), 1.0));
                lo = glm::min(lo, q);
                hi = glm::max(hi, q);
                any = true;
            }
        }
    }
    return any && std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z);
}

std::string GltfModel::emptyReason() const {
    size_t nonFinite = 0, degenerate = 0, outside = 0;
    for (const auto& [key, g] : prims_)
        if (g) nonFinite += g->droppedNonFinite, degenerate += g->droppedDegenerate, outside += g->outsideBounds;
    if (outside)
        return "the model has no triangles to render (" + std::to_string(outside) +
               " vertices lie outside POSITION's declared min/max: corrupt data?)";
    if (nonFinite) return "the model has no triangles to render (" + std::to_string(nonFinite) + " have non-finite positions)";
    if (degenerate) return "the model has no triangles to render (" + std::to_string(degenerate) + " are degenerate)";
    if (order_.empty()) return "the model's scene has no nodes, so there is nothing to render";
    return "the model has no triangles to render";
}

const PrimitiveGeometry* GltfModel::primitive(int mesh, int prim) {
    const auto key = std::make_pair(mesh, prim);
    auto it = prims_.find(key);
    if (it == prims_.end()) {
        PrimitiveGeometry g;
        const bool drawable = buildPrimitive(model_, mesh, prim, path_, g, materialOverride_ < 0);
        it = prims_.emplace(key, drawable ? std::optional<PrimitiveGeometry>(std::move(g)) : std::nullopt).first;
        if (drawable) notePrimitive(*it->second, "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(prim) + "]");
    }
    return it->second ? &*it->second : nullptr;
}

void GltfModel::notePrimitive(const PrimitiveGeometry& g, const std::string& w) {
    if (g.outsideBounds)
        notes_.push_back(w + ": " + std::to_string(g.outsideBounds) +
                         " vertices lie outside POSITION's declared min/max (corrupt data?); their triangles dropped");
    if (g.boundsMissing) notes_.push_back(w + ": POSITION has no min/max (glTF requires them); positions not checked");
    if (g.leftoverIndices)
        notes_.push_back(w + ": " + std::to_string(g.leftoverIndices) + " trailing indices ignored (" +
                         (g.wire ? "LINES needs a multiple of 2" : "TRIANGLES needs a multiple of 3") + ")");
    if (g.materialOutOfRange)
        notes_.push_back(w + ".material: no such material (" + std::to_string(model_.materials.size()) +
                         " in the file); drawn with the default material");
}

void GltfModel::chooseMaterialVariant() {
    const std::vector<std::string> names = materialVariants(model_);
    if (assets_.variant.empty()) {
        if (!names.empty())
            notes_.push_back("material variants " + listVariants(names) + "; showing the default materials (--variant NAME picks one)");
        return;
    }
    if (names.empty() && !assets_.variantRequired) return;
    variant_ = chooseVariant(model_, path_, assets_.variant, assets_.variantSource);
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
        std::optional<PrimitiveGeometry> wired;
        if (g->wire) {
            // Points and lines become small spheres and capsules of the world radius, in the
            // node's own space (its scale taken out, as the cube root of its volume scale).
            const double scale = std::cbrt(std::abs(glm::determinant(glm::dmat3(renderFromNode))));
            if (!(scale > 0.0) || !std::isfinite(scale)) {
                ++dropped.unplaced;
                continue;
            }
            wired = wireGeometry(*g, float(wireRadius_ / scale));
            g = &*wired;
            ++dropped.wires;
        }
        dropped.degenerate += g->droppedDegenerate;
        dropped.nonFinite += g->droppedNonFinite;
        dropped.generated += g->generatedNormals;
        if (g->mesh.indices.empty()) continue;
        const auto instanced = gpuInstances_.find(node);
        if (skinnedPrimitive(node, *g, int(p))) {
            dropped.skinnedInstanced += instanced != gpuInstances_.end();
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
        TriangleMesh m = instanced == gpuInstances_.end() ? g->mesh : instancedPrimitive(g->mesh, instanced->second, dropped.instancesUnplaced);
        if (m.indices.empty()) continue;
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
void GltfModel::addNodeLightAndCamera(Scene& scene, int node, const DMat4& renderFromNode, bool withLight) {
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    if (auto it = n.extensions.find("KHR_lights_punctual"); withLight && it != n.extensions.end() && it->second.Has("light")) {
        const tinygltf::Value& li = it->second.Get("light");
        const int idx = li.IsInt() ? li.Get<int>() : -1;
        if (idx < 0 || size_t(idx) >= model_.lights.size())
            throw InputError(path_, "nodes[" + std::to_string(node) + "]: no light " + std::to_string(idx));
        Light L = punctualLight(model_.lights[size_t(idx)], renderFromNode, path_, idx);
        L.model = int(scene.geometry.models.size()) - 1;
        L.node = node;
        L.source = idx;
        scene.lights.push_back(std::move(L));
    }
    if (n.camera >= 0) {
        if (size_t(n.camera) >= model_.cameras.size())
            throw InputError(path_, "nodes[" + std::to_string(node) + "].camera: no such camera");
        std::string why, fault;
        if (auto c = gltfCamera(model_.cameras[size_t(n.camera)], renderFromNode, why, fault)) {
            scene.gltfCameras.push_back(*c);
            scene.gltfCameraNodes.push_back({int(scene.geometry.models.size()) - 1, node, n.camera});
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
    if (d.instancesUnplaced)
        notes_.push_back(std::to_string(d.instancesUnplaced) + " EXT_mesh_gpu_instancing instances (per primitive) dropped: their SCALE is zero");
    if (d.skinnedInstanced)
        notes_.push_back(std::to_string(d.skinnedInstanced) + " skinned primitives of instanced nodes drawn once, by their skin (EXT_mesh_gpu_instancing leaves skins out)");
    if (d.wires)
        notes_.push_back(std::to_string(d.wires) + " primitives of points or lines drawn as dots and lines " +
                         formatted(2.0 * wireRadius_) + " units wide (--point-size)");
    if (weightsNormalized_)
        notes_.push_back(std::to_string(weightsNormalized_) + " skinned vertices have joint weights that do not sum to 1; normalized");
    if (weightsZero_) notes_.push_back(std::to_string(weightsZero_) + " skinned vertices have no joint weight; they follow their first joint");
    for (const auto& [pattern, channels] : pointersIgnored_)
        notes_.push_back("KHR_animation_pointer: " + std::to_string(channels) + (channels == 1 ? " channel animates " : " channels animate ") +
                         pattern + ", which rayfarm does not animate (it keeps the file's value)");
    // Material extensions are noted per material, where they are met; the animation pointer's
    // channels just above.
    for (const std::string& e : model_.extensionsUsed)
        if (!isSupportedExtension(e) && e.rfind("KHR_materials_", 0) != 0)
            notes_.push_back("extension " + e + " ignored");
}

void GltfModel::addTo(Scene& scene, const DMat4& worldFromModel, int materialOverride) {
    materialOverride_ = materialOverride;
    const DMat4 renderFromModel = glm::translate(DMat4(1.0), -scene.renderOrigin) * worldFromModel;
    const int modelIndex = int(scene.geometry.models.size());
    scene.geometry.models.push_back(sceneGraph(renderFromModel));

    // A node moves if it, or any ancestor, is animated (order_ lists parents first).
    std::vector<uint8_t> dynamic(model_.nodes.size(), 0);
    for (int i : order_) dynamic[size_t(i)] = animatedNode_[size_t(i)] || (parent_[size_t(i)] >= 0 && dynamic[size_t(parent_[size_t(i)])]);

    // Every light of the file, as a scene file's are, before anything is built from it.
    const tinygltf::Value* rawLights = nullptr;
    if (auto e = model_.extensions.find("KHR_lights_punctual"); e != model_.extensions.end() && e->second.Has("lights"))
        rawLights = &e->second.Get("lights");
    for (size_t i = 0; i < model_.lights.size(); ++i) {
        const bool rangeGiven = rawLights && rawLights->IsArray() && i < rawLights->ArrayLen() && rawLights->Get(int(i)).Has("range");
        checkPunctualLight(model_.lights[i], rangeGiven, path_, int(i));
    }

    // Points and lines: --point-size pixels wide in a bare model's default 640×360 turntable,
    // whose fit (anim/turntable_fit) shows the model's diagonal some 280 (the Asset Generator's
    // flat square, at a slant) to 630 pixels long (Blender's points_lines.glb: a cube, a ring
    // and a helix), as estimated from those pictures; 480 lies between.
    bool wires = false;
    for (int node : order_)
        if (const int mesh = model_.nodes[size_t(node)].mesh; mesh >= 0)
            for (const tinygltf::Primitive& p : model_.meshes[size_t(mesh)].primitives) wires |= p.mode >= 0 && p.mode <= 3;
    if (wires) {
        glm::dvec3 lo, hi;
        const double diagonal = bounds(worldFromModel, lo, hi) ? glm::length(hi - lo) : 0.0;
        wireRadius_ = 0.5 * double(assets_.pointSize) * (diagonal > 0.0 ? diagonal : 1.0) / kWireDiagonalPixels;
    }

    // KHR_node_visibility: a node not visible hides its subtree. One that no animation can show
    // is left out; one whose visibility (or a parent's) is animated is drawn, and the
    // animation's player hides it while it is not visible.
    std::vector<uint8_t> hidden(model_.nodes.size(), 0), canShow(model_.nodes.size(), 0);
    for (int i : order_) {
        const int p = parent_[size_t(i)];
        hidden[size_t(i)] = !nodeVisible(i) || (p >= 0 && hidden[size_t(p)]);
        canShow[size_t(i)] = visibilityAnimated_[size_t(i)] || (p >= 0 && canShow[size_t(p)]);
    }

    LoadStep step("building its meshes and materials");
    MaterialBuilder materials(scene, model_, path_, assets_);
    DropCounts dropped;
    const size_t firstMesh = scene.geometry.meshes.size(), firstLight = scene.lights.size();
    for (int node : order_) {
        pollLoadCancel();
        const DMat4 renderFromNode = renderFromModel * modelFromNode_[size_t(node)];
        const bool shown = !hidden[size_t(node)] || canShow[size_t(node)];  // (its cameras work either way)
        if (shown) addNodeMeshes(scene, node, renderFromNode, modelIndex, dynamic[size_t(node)] != 0, materials, dropped);
        addNodeLightAndCamera(scene, node, renderFromNode, shown);
    }
    noteDrops(dropped);
    // Hidden at rest, shown by some animation: collapsed and dark until a player shows them, so
    // a film that plays no such animation (or a still) does not show them either. Joints keep
    // their place (a skin on a shown node follows them).
    std::vector<uint8_t> joint(model_.nodes.size(), 0);
    for (const Skin& sk : skins_)
        for (int j : sk.joints)
            if (j >= 0 && size_t(j) < joint.size()) joint[size_t(j)] = 1;
    for (size_t i = firstMesh; i < scene.geometry.meshes.size(); ++i) {
        TriangleMesh& m = scene.geometry.meshes[i];
        if (m.node >= 0 && hidden[size_t(m.node)] && !joint[size_t(m.node)]) poseMesh(m, DMat4(0.0), nullptr, nullptr);
    }
    for (size_t i = firstLight; i < scene.lights.size(); ++i) {
        Light& L = scene.lights[i];
        if (L.node < 0 || !hidden[size_t(L.node)]) continue;
        scene.geometry.models.back().restHiddenLights.push_back({int(i), L.intensity});
        L.intensity = 0.f;
    }
    addAnimatedMaterials(scene.geometry.models.back(), materials);
    for (const std::string& n : notes_) scene.notes.push_back(path_ + ": " + n);
}

void GltfModel::releaseLoadData() {
    prims_.clear();
    gpuInstances_.clear();
    for (tinygltf::Buffer& b : model_.buffers) std::vector<unsigned char>().swap(b.data);
    for (tinygltf::Image& im : model_.images) std::vector<unsigned char>().swap(im.image);
}

bool GltfModel::nodeVisible(int node) const {
    const tinygltf::Node& n = model_.nodes[size_t(node)];
    auto it = n.extensions.find("KHR_node_visibility");
    if (it == n.extensions.end() || !it->second.Has("visible") || !it->second.Get("visible").IsBool()) return true;
    return it->second.Get("visible").Get<bool>();
}

void GltfModel::addAnimatedMaterials(SceneGraph& graph, const MaterialBuilder& materials) const {
    std::set<int> animated;
    for (const Animation& a : animations_)
        for (const PropertyChannel& pc : a.properties)
            if (pc.property >= AnimProperty::BaseColor && pc.property != AnimProperty::NodeVisible) animated.insert(pc.target);
    for (int file : animated) {
        const tinygltf::Material& gm = model_.materials[size_t(file)];
        AnimatedMaterial am;
        am.file = file;
        am.scene = materialOverride_ >= 0 ? -1 : materials.converted(file);
        if (gm.emissiveFactor.size() == 3)  // clamped as the material loader clamps it
            for (int c = 0; c < 3; ++c) am.emissiveFactor[c] = float(std::clamp(gm.emissiveFactor[size_t(c)], 0.0, 1.0));
        auto number = [](const tinygltf::Value& v, const char* key, double fallback) {
            return v.Has(key) && v.Get(key).IsNumber() ? v.Get(key).GetNumberAsDouble() : fallback;
        };
        if (auto e = gm.extensions.find("KHR_materials_emissive_strength"); e != gm.extensions.end())
            am.emissiveStrength = float(std::max(0.0, number(e->second, "emissiveStrength", 1.0)));
        if (auto e = gm.extensions.find("KHR_materials_volume"); e != gm.extensions.end()) {
            const double d = number(e->second, "attenuationDistance", 0.0);
            am.attenuationDistance = d > 0.0 && std::isfinite(d) ? float(d) : 0.f;
            if (e->second.Has("attenuationColor") && e->second.Get("attenuationColor").IsArray() &&
                e->second.Get("attenuationColor").ArrayLen() == 3)
                for (int c = 0; c < 3; ++c) {
                    const tinygltf::Value& x = e->second.Get("attenuationColor").Get(c);
                    am.attenuationColor[c] = x.IsNumber() ? float(std::clamp(x.GetNumberAsDouble(), 0.0, 1.0)) : 1.f;
                }
        }
        graph.animatedMaterials.push_back(am);
    }
}

}  // namespace rf::gltf
