#include "engine/load/gltf/gltf_instancing.h"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "engine/util/errors.h"
#include "engine/util/load_control.h"
#include "engine/load/gltf/gltf_accessors.h"

namespace rf::gltf {

namespace {

constexpr const char* kExtension = "EXT_mesh_gpu_instancing";
constexpr const char* kAttributes[3] = {"TRANSLATION", "ROTATION", "SCALE"};

/// The node's extension object, or nullptr without the extension.
const tinygltf::Value* extensionOf(const tinygltf::Model& model, int node) {
    const tinygltf::Node& n = model.nodes[size_t(node)];
    auto it = n.extensions.find(kExtension);
    return it == n.extensions.end() ? nullptr : &it->second;
}

/// The accessor index named by attribute `name`, or -1; throws when it names no accessor.
int attributeAccessor(const tinygltf::Model& model, const tinygltf::Value& attrs, const char* name, const std::string& w,
                      const std::string& file) {
    if (!attrs.IsObject() || !attrs.Has(name)) return -1;
    const tinygltf::Value& v = attrs.Get(name);
    const int a = v.IsInt() ? v.Get<int>() : -1;
    if (a < 0 || size_t(a) >= model.accessors.size())
        throw InputError(file, w + ".attributes." + name + ": no accessor " + (v.IsInt() ? std::to_string(a) : std::string("(not an index)")));
    return a;
}

}  // namespace

uint64_t gpuInstanceCount(const tinygltf::Model& model, int node) {
    const tinygltf::Value* ext = extensionOf(model, node);
    if (!ext || !ext->Has("attributes") || !ext->Get("attributes").IsObject()) return 1;
    const tinygltf::Value* attrs = &ext->Get("attributes");
    uint64_t count = 0;
    for (const char* name : kAttributes) {
        if (!attrs->Has(name) || !attrs->Get(name).IsInt()) continue;
        const int a = attrs->Get(name).Get<int>();
        if (a >= 0 && size_t(a) < model.accessors.size()) count = std::max<uint64_t>(count, model.accessors[size_t(a)].count);
    }
    return count;
}

GpuInstances readGpuInstances(const tinygltf::Model& model, int node, const std::string& file) {
    GpuInstances out;
    const tinygltf::Value* ext = extensionOf(model, node);
    if (!ext) return out;
    out.present = true;
    const std::string w = "nodes[" + std::to_string(node) + "].extensions." + kExtension;
    if (!ext->IsObject() || !ext->Has("attributes") || !ext->Get("attributes").IsObject())
        throw InputError(file, w + ": no attributes (TRANSLATION, ROTATION or SCALE)");
    const tinygltf::Value* attrs = &ext->Get("attributes");
    AccessorData data[3];
    size_t count = 0;
    int given = 0, first = -1;
    for (int k = 0; k < 3; ++k) {
        const int a = attributeAccessor(model, *attrs, kAttributes[k], w, file);
        if (a < 0) continue;
        const tinygltf::Accessor& acc = model.accessors[size_t(a)];
        const bool floats = acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
        const bool normalizedInt = acc.normalized && (acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
                                                      acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT ||
                                                      (k != 1 && (acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                                  acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)));
        const std::string what = w + ".attributes." + kAttributes[k] + " (accessors[" + std::to_string(a) + "])";
        if (acc.type != (k == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3))
            throw InputError(file, what + ": must be " + (k == 1 ? "VEC4 (a quaternion)" : "VEC3"));
        if (!floats && !normalizedInt)
            throw InputError(file, what + ": must be float or normalized " + (k == 1 ? "signed " : "") + "byte or short");
        data[k] = readAccessor(model, a, file, {k == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3});
        if (given && data[k].count != count)
            throw InputError(file, what + ": " + std::to_string(data[k].count) + " instances, but " + kAttributes[first] +
                                       " has " + std::to_string(count) + "; every attribute must have the same count");
        count = data[k].count;
        if (!given) first = k;
        ++given;
        for (float x : data[k].values)
            if (!std::isfinite(x)) throw InputError(file, what + ": a value is not finite");
    }
    if (!given) throw InputError(file, w + ": no attributes (TRANSLATION, ROTATION or SCALE)");
    out.nodeFromInstance.reserve(count);
    for (size_t i = 0; i < count; ++i) {
        if (i % 65536 == 0) pollLoadCancel();
        DMat4 t(1.0), r(1.0), s(1.0);
        if (data[0].count) t = glm::translate(DMat4(1.0), glm::dvec3(data[0].at(i, 0), data[0].at(i, 1), data[0].at(i, 2)));
        if (data[1].count) {
            DQuat q(data[1].at(i, 3), data[1].at(i, 0), data[1].at(i, 1), data[1].at(i, 2));  // glTF xyzw → glm wxyz
            const double len = glm::length(q);
            if (!(len > 0.0))
                throw InputError(file, w + ".attributes.ROTATION: instance " + std::to_string(i) + " is not a usable quaternion");
            r = glm::mat4_cast(q / len);
        }
        if (data[2].count) s = glm::scale(DMat4(1.0), glm::dvec3(data[2].at(i, 0), data[2].at(i, 1), data[2].at(i, 2)));
        out.nodeFromInstance.push_back(t * r * s);
    }
    return out;
}

TriangleMesh instancedPrimitive(const TriangleMesh& g, const std::vector<DMat4>& nodeFromInstance, size_t& unplaced) {
    TriangleMesh m = g;
    const size_t nv = g.positions.size();
    auto clearData = [&](TriangleMesh& x) {
        x.positions.clear(), x.normals.clear(), x.uvs.clear(), x.uvs1.clear(), x.tangents.clear(), x.colors.clear(), x.indices.clear();
        for (auto& d : x.morphPositions) d.clear();
        for (auto& d : x.morphNormals) d.clear();
        for (auto& d : x.morphTangents) d.clear();
    };
    clearData(m);
    size_t placed = 0;
    for (const DMat4& M : nodeFromInstance) {
        const glm::dmat3 l(M);
        const double det = glm::determinant(l);
        if (!(std::abs(det) > 0.0) || !std::isfinite(det)) {
            ++unplaced;
            continue;
        }
        const glm::dmat3 nm = glm::transpose(glm::inverse(l));
        const uint32_t base = uint32_t(placed * nv);
        ++placed;
        for (const Vec3& p : g.positions) m.positions.push_back(Vec3(glm::dvec3(M * glm::dvec4(glm::dvec3(p), 1.0))));
        auto direction = [](const glm::dmat3& a, const Vec3& v) {
            const glm::dvec3 d = a * glm::dvec3(v);
            const double len = glm::length(d);
            return len > 0.0 && std::isfinite(len) ? Vec3(d / len) : Vec3(0.f);
        };
        for (const Vec3& n : g.normals) m.normals.push_back(direction(nm, n));
        for (const Vec4& t : g.tangents) m.tangents.push_back(Vec4(direction(l, Vec3(t)), det < 0.0 ? -t.w : t.w));
        m.uvs.insert(m.uvs.end(), g.uvs.begin(), g.uvs.end());
        m.uvs1.insert(m.uvs1.end(), g.uvs1.begin(), g.uvs1.end());
        m.colors.insert(m.colors.end(), g.colors.begin(), g.colors.end());
        // Morph offsets are differences of positions (and of normals, tangents): the linear part.
        for (size_t k = 0; k < g.morphPositions.size(); ++k)
            for (const Vec3& d : g.morphPositions[k]) m.morphPositions[k].push_back(Vec3(l * glm::dvec3(d)));
        for (size_t k = 0; k < g.morphNormals.size(); ++k)
            for (const Vec3& d : g.morphNormals[k]) m.morphNormals[k].push_back(Vec3(nm * glm::dvec3(d)));
        for (size_t k = 0; k < g.morphTangents.size(); ++k)
            for (const Vec3& d : g.morphTangents[k]) m.morphTangents[k].push_back(Vec3(l * glm::dvec3(d)));
        // A mirroring instance turns the file's counter-clockwise front faces round: swap two
        // corners so they stay in front, as a mirroring static node's do.
        for (size_t t = 0; t + 2 < g.indices.size(); t += 3) {
            m.indices.push_back(base + g.indices[t]);
            m.indices.push_back(base + g.indices[t + (det < 0.0 ? 2 : 1)]);
            m.indices.push_back(base + g.indices[t + (det < 0.0 ? 1 : 2)]);
        }
    }
    return m;
}

}  // namespace rf::gltf
