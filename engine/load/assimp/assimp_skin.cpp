#include "engine/load/assimp/assimp_skin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <assimp/mesh.h>
#include <assimp/scene.h>

#include "engine/util/errors.h"

namespace rf {

namespace {

struct Influence {
    uint32_t joint;
    float weight;
};

bool usable(const aiVertexWeight& w, size_t vertices) { return w.mVertexId < vertices && w.mWeight > 0.f && std::isfinite(w.mWeight); }

/// The offset matrix (row-major, column vectors) as glTF's column-major floats.
void appendColumnMajor(const aiMatrix4x4& t, std::vector<float>& out) {
    const float rows[4][4] = {{t.a1, t.a2, t.a3, t.a4}, {t.b1, t.b2, t.b3, t.b4}, {t.c1, t.c2, t.c3, t.c4}, {t.d1, t.d2, t.d3, t.d4}};
    for (int col = 0; col < 4; ++col)
        for (int r = 0; r < 4; ++r) out.push_back(rows[r][col]);
}

}  // namespace

AssimpSkin assimpSkin(const aiMesh& m) {
    AssimpSkin s;
    if (m.mNumBones == 0 || !m.mBones) return s;
    const size_t n = m.mNumVertices;
    // A joint index is an unsigned short in glTF; one more is kept for the mesh's own node.
    if (m.mNumBones >= std::numeric_limits<uint16_t>::max()) {
        s.refused = std::to_string(m.mNumBones) + " bones, more than a glTF skin's 65534";
        return s;
    }
    for (unsigned b = 0; b < m.mNumBones; ++b) {
        const aiBone* bone = m.mBones[b];
        if (!bone) {
            s.refused = "bone " + std::to_string(b) + " missing";
            return s;
        }
        const aiMatrix4x4& t = bone->mOffsetMatrix;
        const float all[16] = {t.a1, t.a2, t.a3, t.a4, t.b1, t.b2, t.b3, t.b4, t.c1, t.c2, t.c3, t.c4, t.d1, t.d2, t.d3, t.d4};
        if (!std::all_of(std::begin(all), std::end(all), [](float v) { return std::isfinite(v); })) {
            s.refused = "bone \"" + std::string(bone->mName.C_Str()) + "\" has a non-finite offset matrix";
            return s;
        }
        s.jointNames.emplace_back(bone->mName.C_Str());
        appendColumnMajor(t, s.inverseBind);
    }

    // Each vertex's influences, gathered from the bones' lists in two passes (count, then fill)
    // into one array indexed by vertex, so memory stays linear in the weights.
    std::vector<size_t> start(n + 1, 0);
    for (unsigned b = 0; b < m.mNumBones; ++b)
        for (unsigned k = 0; k < m.mBones[b]->mNumWeights && m.mBones[b]->mWeights; ++k) {
            const aiVertexWeight& w = m.mBones[b]->mWeights[k];
            if (usable(w, n)) ++start[w.mVertexId + 1];
            else ++s.weightsDropped;
        }
    for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<Influence> all(start[n]);
    std::vector<size_t> fill(start.begin(), start.end() - 1);
    for (unsigned b = 0; b < m.mNumBones; ++b)
        for (unsigned k = 0; k < m.mBones[b]->mNumWeights && m.mBones[b]->mWeights; ++k) {
            const aiVertexWeight& w = m.mBones[b]->mWeights[k];
            if (usable(w, n)) all[fill[w.mVertexId]++] = {b, w.mWeight};
        }

    size_t most = 1;
    for (size_t v = 0; v < n; ++v) most = std::max(most, start[v + 1] - start[v]);
    const size_t kept = std::min<size_t>(most, AssimpSkin::kMaxInfluences);
    s.sets = int((kept + 3) / 4);
    const size_t width = size_t(4 * s.sets);
    s.joints.assign(n * width, 0);
    s.weights.assign(n * width, 0.f);
    const auto self = uint16_t(m.mNumBones);  // the mesh's own node, added below if used
    for (size_t v = 0; v < n; ++v) {
        Influence* first = all.data() + start[v];
        Influence* last = all.data() + start[v + 1];
        if (first == last) {
            s.joints[v * width] = self;
            s.weights[v * width] = 1.f;
            ++s.unweighted;
            continue;
        }
        size_t count = size_t(last - first);
        if (count > kept) {
            // The largest weights: the pose the file means, less the smallest pulls.
            std::partial_sort(first, first + kept, last, [](const Influence& a, const Influence& b) { return a.weight > b.weight; });
            count = kept;
            ++s.verticesOverCap;
        }
        // Divided by their sum, as Blender's armature deform and FBX's and COLLADA's authoring
        // tools pose a vertex: their exporters write the weights as painted, rarely summing to 1.
        double sum = 0.0;
        for (size_t k = 0; k < count; ++k) sum += first[k].weight;
        for (size_t k = 0; k < count; ++k) {
            s.joints[v * width + k] = uint16_t(first[k].joint);
            s.weights[v * width + k] = float(first[k].weight / sum);
        }
    }
    if (s.unweighted) {
        s.jointNames.emplace_back();
        appendColumnMajor(aiMatrix4x4(), s.inverseBind);
    }
    return s;
}

void makeSkins(tinygltf::Model& g, const aiScene& scene, const std::vector<AssimpSkin>& skins, const std::vector<OwnNode>& skinned,
               const std::map<std::string, int>& nodeByName, std::vector<std::string>& notes,
               const std::function<int(const std::vector<float>&)>& mat4Accessor) {
    std::map<unsigned, int> inverseBindOf;  // one accessor a mesh, whichever nodes draw it
    std::set<unsigned> posed;
    for (const OwnNode& sn : skinned) {
        const AssimpSkin& s = skins[sn.mesh];
        if (s.sets == 0) continue;
        const std::string mesh = "mesh \"" + printable(scene.mMeshes[sn.mesh]->mName.C_Str()) + "\"";
        tinygltf::Skin skin;
        skin.name = scene.mMeshes[sn.mesh]->mName.C_Str();
        for (const std::string& name : s.jointNames) {
            const auto it = name.empty() ? nodeByName.end() : nodeByName.find(name);
            if (!name.empty() && it == nodeByName.end()) {
                notes.push_back(mesh + " drawn in its bind pose: its bone \"" + printable(name) + "\" names no node");
                skin.joints.clear();
                break;
            }
            skin.joints.push_back(name.empty() ? sn.holder : it->second);
        }
        if (skin.joints.empty()) continue;
        auto [ibm, fresh] = inverseBindOf.try_emplace(sn.mesh, -1);
        if (fresh) ibm->second = mat4Accessor(s.inverseBind);
        skin.inverseBindMatrices = ibm->second;
        g.skins.push_back(std::move(skin));
        g.nodes[size_t(sn.node)].skin = int(g.skins.size() - 1);
        if (!posed.insert(sn.mesh).second) continue;
        if (s.verticesOverCap)
            notes.push_back(mesh + ": " + std::to_string(s.verticesOverCap) + " vertices weighted by more than " +
                            std::to_string(AssimpSkin::kMaxInfluences) + " bones follow their " +
                            std::to_string(AssimpSkin::kMaxInfluences) + " largest weights, scaled to sum to 1");
        if (s.unweighted)
            notes.push_back(mesh + ": " + std::to_string(s.unweighted) + " vertices that no bone weighs stay with the mesh's node");
        if (s.weightsDropped)
            notes.push_back(mesh + ": " + std::to_string(s.weightsDropped) + " bone weights negative, not finite or of no vertex; ignored");
    }
}

}  // namespace rf
