#include "engine/load/assimp/assimp_morph.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <assimp/anim.h>
#include <assimp/mesh.h>

namespace rf {

namespace {

/// An offset with its non-finite components as 0 (the glTF loader refuses them; a vertex with
/// a non-finite position is dropped with its triangles anyway).
aiVector3D finite(const aiVector3D& v) {
    return {std::isfinite(v.x) ? v.x : 0.f, std::isfinite(v.y) ? v.y : 0.f, std::isfinite(v.z) ? v.z : 0.f};
}

/// Per vertex, the sum of its triangles' normals, each as long as twice the triangle's area.
std::vector<aiVector3D> faceNormalSums(const aiMesh& m, const aiVector3D* p) {
    std::vector<aiVector3D> sum(m.mNumVertices, aiVector3D(0.f));
    for (unsigned f = 0; f < m.mNumFaces && m.mFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3 || !face.mIndices) continue;
        const unsigned a = face.mIndices[0], b = face.mIndices[1], c = face.mIndices[2];
        if (a >= m.mNumVertices || b >= m.mNumVertices || c >= m.mNumVertices) continue;
        const aiVector3D n = (p[b] - p[a]) ^ (p[c] - p[a]);
        if (!std::isfinite(n.x + n.y + n.z)) continue;
        sum[a] += n, sum[b] += n, sum[c] += n;
    }
    return sum;
}

/// Normal offsets for a target whose file gives none (or none that differ from the base's):
/// each vertex's normal turned as the surface around it turns from the base to the target
/// (the rotation taking the one area-weighted normal to the other), so the file's own
/// normals, smooth or split, keep their character. Blender writes zero normal offsets to an
/// FBX shape and recomputes normals on import; glTF has no "recompute", so they are made here.
std::vector<aiVector3D> derivedNormalOffsets(const aiMesh& m, const aiVector3D* target, const std::vector<aiVector3D>& base) {
    const std::vector<aiVector3D> turned = faceNormalSums(m, target);
    std::vector<aiVector3D> d(m.mNumVertices, aiVector3D(0.f));
    for (size_t i = 0; i < d.size(); ++i) {
        const float la = base[i].Length(), lb = turned[i].Length();
        if (!(la > 0.f) || !(lb > 0.f)) continue;
        const aiVector3D a = base[i] / la, b = turned[i] / lb, n = m.mNormals[i];
        const aiVector3D v = a ^ b;
        const float c = a * b;
        if (c <= -0.999f) continue;  // turned over: no one rotation; left as it was
        // Rodrigues' rotation about a × b by the angle between a and b.
        const aiVector3D vn = v ^ n;
        d[i] = finite(vn + (v ^ vn) / (1.f + c));
    }
    return d;
}

}  // namespace

AssimpMorph assimpMorph(const aiMesh& m) {
    AssimpMorph out;
    if (m.mNumAnimMeshes == 0 || !m.mAnimMeshes || !m.mVertices) return out;
    const size_t n = m.mNumVertices;
    const bool relative = m.mMethod == aiMorphingMethod_MORPH_RELATIVE;
    bool anyNormals = false;
    std::vector<aiVector3D> baseSums;  // made when a target's normals are to be derived
    for (unsigned t = 0; t < m.mNumAnimMeshes; ++t) {
        const aiAnimMesh* a = m.mAnimMeshes[t];
        out.names.emplace_back(a ? a->mName.C_Str() : "");
        std::vector<aiVector3D>& dp = out.positions.emplace_back(n, aiVector3D(0.f));
        std::vector<aiVector3D>& dn = out.normals.emplace_back();
        if (!a || !a->mVertices || a->mNumVertices != n) {
            ++out.unusable;
            continue;
        }
        for (size_t i = 0; i < n; ++i) dp[i] = finite(relative ? a->mVertices[i] : a->mVertices[i] - m.mVertices[i]);
        if (!m.mNormals) continue;
        dn.assign(n, aiVector3D(0.f));
        bool given = false;
        if (a->mNormals)
            for (size_t i = 0; i < n; ++i) {
                dn[i] = finite(relative ? a->mNormals[i] : a->mNormals[i] - m.mNormals[i]);
                // assimp renormalizes the base normal plus the file's offset: an offset of 0
                // comes back as float rounding, not as 0.
                given = given || dn[i].SquareLength() > 1e-8f;
            }
        if (!given && std::any_of(dp.begin(), dp.end(), [](const aiVector3D& v) { return v != aiVector3D(0.f); })) {
            if (baseSums.empty()) baseSums = faceNormalSums(m, m.mVertices);
            std::vector<aiVector3D> whole(n);
            for (size_t i = 0; i < n; ++i) whole[i] = m.mVertices[i] + dp[i];
            dn = derivedNormalOffsets(m, whole.data(), baseSums);
            ++out.derivedNormals;
        }
        anyNormals = true;
    }
    // glTF's targets of a primitive all have the same attributes: normal offsets for every
    // target (zero where one has none) or for none.
    for (std::vector<aiVector3D>& dn : out.normals)
        if (anyNormals) dn.resize(n, aiVector3D(0.f));
        else dn.clear();
    return out;
}

MorphTrack morphTrack(const aiMeshMorphAnim& channel, size_t targets) {
    MorphTrack out;
    if (!channel.mKeys || targets == 0) return out;
    std::vector<std::vector<std::pair<double, float>>> keys(targets);
    for (unsigned k = 0; k < channel.mNumKeys; ++k) {
        const aiMeshMorphKey& key = channel.mKeys[k];
        if (!std::isfinite(key.mTime) || !key.mValues || !key.mWeights) continue;
        bool used = false;
        for (unsigned v = 0; v < key.mNumValuesAndWeights; ++v) {
            if (key.mValues[v] >= targets) {
                ++out.outOfRange;
                continue;
            }
            if (!std::isfinite(key.mWeights[v])) continue;
            keys[key.mValues[v]].emplace_back(key.mTime, float(key.mWeights[v]));
            used = true;
        }
        if (used) out.times.push_back(key.mTime);
    }
    std::sort(out.times.begin(), out.times.end());
    out.times.erase(std::unique(out.times.begin(), out.times.end()), out.times.end());
    for (auto& k : keys) {
        std::stable_sort(k.begin(), k.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        k.erase(std::unique(k.begin(), k.end(), [](const auto& a, const auto& b) { return a.first == b.first; }), k.end());
    }
    out.weights.resize(out.times.size() * targets);
    std::vector<size_t> next(targets, 0);  // each target's first key after the time reached
    for (size_t t = 0; t < out.times.size(); ++t) {
        const double time = out.times[t];
        for (size_t j = 0; j < targets; ++j) {
            const auto& k = keys[j];
            size_t& i = next[j];
            while (i < k.size() && k[i].first <= time) ++i;
            float w = 0.f;
            if (k.empty()) w = 0.f;
            else if (i == 0) w = k.front().second;
            else if (i == k.size() || k[i - 1].first == time) w = k[i - 1].second;
            else {
                const auto& [t0, w0] = k[i - 1];
                const auto& [t1, w1] = k[i];
                w = float(w0 + (w1 - w0) * (time - t0) / (t1 - t0));
            }
            out.weights[t * targets + j] = w;
        }
    }
    return out;
}

std::string morphChannelNode(const std::string& name) {
    const size_t star = name.rfind('*');
    if (star == std::string::npos || star + 1 == name.size()) return name;
    const bool digits = std::all_of(name.begin() + std::ptrdiff_t(star) + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; });
    return digits ? name.substr(0, star) : name;
}

}  // namespace rf
