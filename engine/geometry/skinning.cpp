#include "engine/geometry/skinning.h"

#include <cmath>

namespace rf {

std::vector<DMat4> jointMatrices(const Skin& skin, const std::vector<DMat4>& renderFromNode) {
    std::vector<DMat4> out(skin.joints.size(), DMat4(1.0));
    for (size_t j = 0; j < skin.joints.size(); ++j) {
        const int node = skin.joints[j];
        if (node < 0 || size_t(node) >= renderFromNode.size()) continue;
        out[j] = renderFromNode[size_t(node)] * (j < skin.inverseBind.size() ? skin.inverseBind[j] : DMat4(1.0));
    }
    return out;
}

DMat4 skinMatrix(const TriangleMesh& mesh, size_t vertex, const std::vector<DMat4>& joints) {
    DMat4 m(0.0);
    const size_t k0 = vertex * size_t(mesh.influences);
    for (size_t k = k0; k < k0 + size_t(mesh.influences); ++k) {
        const double w = mesh.skinWeights[k];
        if (w == 0.0) continue;
        const uint16_t j = mesh.skinJoints[k];
        if (j < joints.size()) m += w * joints[j];
    }
    return m;
}

namespace {

Vec3 unitOrZero(const glm::dvec3& v) {
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? Vec3(v / len) : Vec3(0.f);
}

/// Morphed object-space position and normal of vertex i.
void morphed(const TriangleMesh& mesh, size_t i, const std::vector<double>* w, glm::dvec3& p, glm::dvec3& n) {
    p = glm::dvec3(mesh.objectPositions[i]);
    n = mesh.objectNormals.empty() ? glm::dvec3(0.0) : glm::dvec3(mesh.objectNormals[i]);
    if (!w) return;
    for (size_t k = 0; k < w->size() && k < mesh.morphPositions.size(); ++k) {
        p += (*w)[k] * glm::dvec3(mesh.morphPositions[k][i]);
        if (!mesh.objectNormals.empty() && k < mesh.morphNormals.size() && !mesh.morphNormals[k].empty())
            n += (*w)[k] * glm::dvec3(mesh.morphNormals[k][i]);
    }
}

/// Morphed object-space tangent direction of vertex i (glTF morph targets move xyz; w stays).
glm::dvec3 morphedTangent(const TriangleMesh& mesh, size_t i, const std::vector<double>* w) {
    glm::dvec3 t(Vec3(mesh.objectTangents[i]));
    if (!w) return t;
    for (size_t k = 0; k < w->size() && k < mesh.morphTangents.size(); ++k)
        if (!mesh.morphTangents[k].empty()) t += (*w)[k] * glm::dvec3(mesh.morphTangents[k][i]);
    return t;
}

void poseRigid(TriangleMesh& mesh, const DMat4& m, const std::vector<double>* w) {
    mesh.renderFromObject = m;
    const glm::dmat3 nm = glm::transpose(glm::inverse(glm::dmat3(m)));
    // Tangents follow the surface (the linear part itself, not its inverse transpose); a
    // mirroring transform flips the bitangent's sign, as glTF's loader-side rule does.
    const glm::dmat3 lin(m);
    const bool mirror = glm::determinant(lin) < 0.0;
    mesh.mirrored = mirror;
    mesh.mirroredVertices.clear();
    const double tangentSign = mirror ? -1.0 : 1.0;
    for (size_t i = 0; i < mesh.objectTangents.size() && i < mesh.tangents.size(); ++i)
        mesh.tangents[i] = Vec4(unitOrZero(lin * morphedTangent(mesh, i, w)), float(tangentSign * mesh.objectTangents[i].w));
    for (size_t i = 0; i < mesh.objectPositions.size(); ++i) {
        glm::dvec3 p, n;
        morphed(mesh, i, w, p, n);
        mesh.positions[i] = Vec3(glm::dvec3(m * glm::dvec4(p, 1.0)));
        if (!mesh.objectNormals.empty()) {
            const glm::dvec3 tn = nm * n;
            const double len = glm::length(tn);
            mesh.normals[i] = len > 0.0 ? Vec3(tn / len) : Vec3(0.f);
        }
    }
}

void poseSkinned(TriangleMesh& mesh, const std::vector<DMat4>& joints, const std::vector<double>* w) {
    const bool tangents = !mesh.objectTangents.empty() && mesh.tangents.size() == mesh.objectTangents.size();
    mesh.mirrored = false;
    bool anyMirrored = false;
    mesh.mirroredVertices.assign(mesh.objectPositions.size(), 0);
    for (size_t i = 0; i < mesh.objectPositions.size(); ++i) {
        const DMat4 s = skinMatrix(mesh, i, joints);
        glm::dvec3 p, n;
        morphed(mesh, i, w, p, n);
        mesh.positions[i] = Vec3(glm::dvec3(s * glm::dvec4(p, 1.0)));
        const glm::dmat3 lin(s);
        // A mirroring skin matrix (a joint scaled by −1, a mirrored rig) turns the vertex's
        // faces round and its tangent frame's handedness, as a mirroring node matrix does.
        const bool mirror = glm::determinant(lin) < 0.0;
        mesh.mirroredVertices[i] = mirror;
        anyMirrored |= mirror;
        if (!mesh.objectNormals.empty()) {
            // The inverse transpose up to a positive factor: the cofactor matrix (columns
            // c1×c2, c2×c0, c0×c1) times the sign of the determinant. Normalizing drops the rest.
            const glm::dmat3 cof(glm::cross(lin[1], lin[2]), glm::cross(lin[2], lin[0]), glm::cross(lin[0], lin[1]));
            mesh.normals[i] = unitOrZero((mirror ? -1.0 : 1.0) * (cof * n));
        }
        if (tangents) {
            const float tw = mesh.objectTangents[i].w;
            mesh.tangents[i] = Vec4(unitOrZero(lin * morphedTangent(mesh, i, w)), mirror ? -tw : tw);
        }
    }
    if (!anyMirrored) mesh.mirroredVertices.clear();
}

}  // namespace

void poseMesh(TriangleMesh& mesh, const DMat4& renderFromNode, const std::vector<DMat4>* joints,
              const std::vector<double>* weights) {
    if (mesh.skin >= 0 && joints) poseSkinned(mesh, *joints, weights);
    else poseRigid(mesh, renderFromNode, weights);
}

}  // namespace rf
