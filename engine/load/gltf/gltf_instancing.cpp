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
    for (const std::string& name : attrs->Keys()) {
        if (!attrs->Get(name).IsInt()) continue;
        const int a = attrs->Get(name).Get<int>();
        if (a >= 0 && size_t(a) < model.accessors.size()) count = std::max<uint64_t>(count, model.accessors[size_t(a)].count);
    }
    return count;
}

DMat4 InstanceTrs::matrix() const {
    const DMat4 tm = glm::translate(DMat4(1.0), glm::dvec3(t[0], t[1], t[2]));
    const DMat4 rm = glm::mat4_cast(DQuat(r[3], r[0], r[1], r[2]));  // glTF xyzw → glm wxyz
    return tm * rm * glm::scale(DMat4(1.0), glm::dvec3(s[0], s[1], s[2]));
}

GpuInstances readGpuInstances(const tinygltf::Model& model, int node, const std::string& file) {
    GpuInstances out;
    const tinygltf::Value* ext = extensionOf(model, node);
    if (!ext) return out;
    out.present = true;
    const std::string w = "nodes[" + std::to_string(node) + "].extensions." + kExtension;
    if (!ext->IsObject() || !ext->Has("attributes") || !ext->Get("attributes").IsObject() || ext->Get("attributes").Keys().empty())
        throw InputError(file, w + ": no attributes (TRANSLATION, ROTATION, SCALE or an application's own)");
    const tinygltf::Value* attrs = &ext->Get("attributes");
    AccessorData data[3];
    size_t count = 0;
    std::string first;  // the attribute the count was taken from
    auto setCount = [&](size_t n, const std::string& name, const std::string& what) {
        if (!first.empty() && n != count)
            throw InputError(file, what + ": " + std::to_string(n) + " instances, but " + first + " has " + std::to_string(count) +
                                       "; every attribute must have the same count");
        count = n;
        if (first.empty()) first = name;
    };
    for (int k = 0; k < 3; ++k) {
        const int a = attributeAccessor(model, *attrs, kAttributes[k], w, file);
        if (a < 0) continue;
        const tinygltf::Accessor& acc = model.accessors[size_t(a)];
        const std::string what = w + ".attributes." + kAttributes[k] + " (accessors[" + std::to_string(a) + "])";
        if (acc.type != (k == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3))
            throw InputError(file, what + ": must be " + (k == 1 ? "VEC4 (a quaternion)" : "VEC3"));
        // As a mesh's attributes under KHR_mesh_quantization: a rotation is float or a
        // normalized signed byte or short; a translation and a scale may be any of those, or
        // integers as they are.
        const int c = acc.componentType;
        const bool floats = c == TINYGLTF_COMPONENT_TYPE_FLOAT;
        const bool signedNormalized = acc.normalized && (c == TINYGLTF_COMPONENT_TYPE_BYTE || c == TINYGLTF_COMPONENT_TYPE_SHORT);
        const bool smallInt = c == TINYGLTF_COMPONENT_TYPE_BYTE || c == TINYGLTF_COMPONENT_TYPE_SHORT ||
                              c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
        if (k == 1 ? !(floats || signedNormalized) : !(floats || smallInt))
            throw InputError(file, what + (k == 1 ? ": must be float or normalized signed byte or short"
                                                  : ": must be float, or byte or short (normalized or not)"));
        data[k] = readAccessor(model, a, file, {k == 1 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3});
        setCount(data[k].count, kAttributes[k], what);
        for (float x : data[k].values)
            if (!std::isfinite(x)) throw InputError(file, what + ": a value is not finite");
    }
    // An application's own attributes ("_ID"): only their count is read.
    for (const std::string& name : attrs->Keys()) {
        if (name == kAttributes[0] || name == kAttributes[1] || name == kAttributes[2]) continue;
        const int a = attributeAccessor(model, *attrs, name.c_str(), w, file);
        setCount(model.accessors[size_t(a)].count, name, w + ".attributes." + name + " (accessors[" + std::to_string(a) + "])");
    }
    out.instances.resize(count);
    for (size_t i = 0; i < count; ++i) {
        if (i % 65536 == 0) pollLoadCancel();
        InstanceTrs& in = out.instances[i];
        for (int c = 0; c < 3 && data[0].count; ++c) in.t[c] = data[0].at(i, c);
        for (int c = 0; c < 3 && data[2].count; ++c) in.s[c] = data[2].at(i, c);
        if (data[1].count) {
            const double x = data[1].at(i, 0), y = data[1].at(i, 1), z = data[1].at(i, 2), q = data[1].at(i, 3);
            const double len = std::sqrt(x * x + y * y + z * z + q * q);
            if (!(len > 0.0))
                throw InputError(file, w + ".attributes.ROTATION: instance " + std::to_string(i) + " is not a usable quaternion");
            in.r[0] = float(x / len), in.r[1] = float(y / len), in.r[2] = float(z / len), in.r[3] = float(q / len);
        }
    }
    return out;
}

TriangleMesh instancedPrimitive(const TriangleMesh& g, const std::vector<InstanceTrs>& instances, size_t& unplaced) {
    TriangleMesh m = g;
    const size_t nv = g.positions.size(), n = instances.size();
    // Each array once at its full size: instances x vertices may be tens of millions.
    auto sized = [&](auto& out, const auto& in) {
        out.clear();
        out.reserve(in.size() * n);
    };
    sized(m.positions, g.positions), sized(m.normals, g.normals), sized(m.uvs, g.uvs), sized(m.uvs1, g.uvs1);
    sized(m.tangents, g.tangents), sized(m.colors, g.colors), sized(m.indices, g.indices);
    for (size_t k = 0; k < g.morphPositions.size(); ++k) sized(m.morphPositions[k], g.morphPositions[k]);
    for (size_t k = 0; k < g.morphNormals.size(); ++k) sized(m.morphNormals[k], g.morphNormals[k]);
    for (size_t k = 0; k < g.morphTangents.size(); ++k) sized(m.morphTangents[k], g.morphTangents[k]);
    size_t placed = 0;
    for (const InstanceTrs& trs : instances) {
        const DMat4 M = trs.matrix();
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
