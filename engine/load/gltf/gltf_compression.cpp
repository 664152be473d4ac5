#include "engine/load/gltf/gltf_compression.h"

#include <cstring>

#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_accessors.h"
#include "engine/load/gltf/gltf_safety.h"

namespace rf::gltf {

namespace {

int typeComponents(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;  // matrices are never vertex attributes
    }
}

/// A new buffer holding `bytes`, and a bufferView over all of it; returns the view's index.
int appendBuffer(tinygltf::Model& model, std::vector<unsigned char> bytes) {
    tinygltf::BufferView view;
    view.buffer = int(model.buffers.size());
    view.byteOffset = 0;
    view.byteLength = bytes.size();
    tinygltf::Buffer b;
    b.data = std::move(bytes);
    model.buffers.push_back(std::move(b));
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size() - 1);
}

int intMember(const tinygltf::Value& v, const char* key, int fallback) {
    if (!v.Has(key) || !v.Get(key).IsNumber()) return fallback;
    const double d = v.Get(key).GetNumberAsDouble();
    return std::isfinite(d) && d >= -1 && d <= double(INT32_MAX) ? int(d) : fallback;
}

/// Draco attribute values of every point, converted to the accessor's component type.
template <typename T>
std::vector<unsigned char> attributeBytes(const draco::PointAttribute& att, uint32_t points, int comps, const std::string& where,
                                          const std::string& file) {
    std::vector<unsigned char> out(size_t(points) * size_t(comps) * sizeof(T));
    T value[4];
    for (uint32_t p = 0; p < points; ++p) {
        const draco::AttributeValueIndex i = att.mapped_index(draco::PointIndex(p));
        if (i.value() >= att.size() || !att.ConvertValue<T>(i, int8_t(comps), value))
            throw InputError(file, where + ": Draco attribute value " + std::to_string(i.value()) + " cannot be read");
        std::memcpy(out.data() + size_t(p) * comps * sizeof(T), value, comps * sizeof(T));
    }
    return out;
}

/// Replaces one Draco-compressed primitive's attributes and indices by decoded accessors.
void decodeDracoPrimitive(tinygltf::Model& model, tinygltf::Primitive& prim, const tinygltf::Value& ext, const std::string& where,
                          const std::string& file, std::vector<std::string>* notes) {
    const std::string w = where + ".extensions.KHR_draco_mesh_compression";
    const int view = intMember(ext, "bufferView", -1);
    const ByteSpan span = bufferViewSpan(model, view, file);
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(span.data), span.size);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) throw InputError(file, w + ": cannot decode the Draco data (" + decoded.status().error_msg_string() + ")");
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    const uint32_t points = mesh->num_points();
    if (uint64_t(points) > Limits::kMaxAccessorCount || uint64_t(mesh->num_faces()) > Limits::kMaxTriangles)
        throw InputError(file, w + ": " + std::to_string(points) + " points and " + std::to_string(mesh->num_faces()) +
                                   " faces are over the limits");

    if (!ext.Has("attributes") || !ext.Get("attributes").IsObject()) throw InputError(file, w + ".attributes: expected an object");
    const tinygltf::Value& attrs = ext.Get("attributes");
    bool mismatch = false;
    for (const std::string& name : attrs.Keys()) {
        auto it = prim.attributes.find(name);
        if (it == prim.attributes.end()) continue;  // the extension may carry more than the primitive uses
        const std::string wa = w + ".attributes." + name;
        if (it->second < 0 || size_t(it->second) >= model.accessors.size()) throw InputError(file, wa + ": no such accessor");
        const int id = intMember(attrs, name.c_str(), -1);
        const draco::PointAttribute* att = id >= 0 ? mesh->GetAttributeByUniqueId(uint32_t(id)) : nullptr;
        if (!att) throw InputError(file, wa + ": the Draco data has no attribute " + std::to_string(id));
        tinygltf::Accessor acc = model.accessors[size_t(it->second)];
        const int comps = typeComponents(acc.type);
        if (comps == 0 || comps > att->num_components())
            throw InputError(file, wa + ": the accessor's " + std::to_string(comps) + " components do not match the Draco attribute's " +
                                       std::to_string(int(att->num_components())));
        std::vector<unsigned char> bytes;
        switch (acc.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: bytes = attributeBytes<float>(*att, points, comps, wa, file); break;
            case TINYGLTF_COMPONENT_TYPE_BYTE: bytes = attributeBytes<int8_t>(*att, points, comps, wa, file); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: bytes = attributeBytes<uint8_t>(*att, points, comps, wa, file); break;
            case TINYGLTF_COMPONENT_TYPE_SHORT: bytes = attributeBytes<int16_t>(*att, points, comps, wa, file); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: bytes = attributeBytes<uint16_t>(*att, points, comps, wa, file); break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: bytes = attributeBytes<uint32_t>(*att, points, comps, wa, file); break;
            default: throw InputError(file, wa + ": componentType " + std::to_string(acc.componentType) + " is not a glTF type");
        }
        // The extension asks the accessor's count to be the decoded one; where a file disagrees,
        // the data decoded is what is drawn, and the note says so once per primitive.
        if (acc.count != points && notes && !mismatch) {
            notes->push_back(wa + ": the accessor declares " + std::to_string(acc.count) + " vertices, the Draco data decodes " +
                             std::to_string(points) + "; the decoded count is used");
            mismatch = true;
        }
        acc.bufferView = appendBuffer(model, std::move(bytes));
        acc.byteOffset = 0;
        acc.count = points;
        acc.sparse = decltype(acc.sparse){};
        model.accessors.push_back(acc);
        it->second = int(model.accessors.size() - 1);
    }

    // Indices: the faces as unsigned ints (a primitive without indices gets them: Draco's
    // points are not in drawing order).
    std::vector<unsigned char> idx(size_t(mesh->num_faces()) * 3 * 4);
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f)
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh->face(f)[k].value();
            if (v >= points) throw InputError(file, w + ": face " + std::to_string(f.value()) + " names point " + std::to_string(v));
            std::memcpy(idx.data() + (size_t(f.value()) * 3 + k) * 4, &v, 4);
        }
    tinygltf::Accessor ia;
    if (prim.indices >= 0 && size_t(prim.indices) < model.accessors.size()) ia = model.accessors[size_t(prim.indices)];
    if (prim.indices >= 0 && ia.count != size_t(mesh->num_faces()) * 3 && notes)
        notes->push_back(w + ": the index accessor declares " + std::to_string(ia.count) + " indices, the Draco data decodes " +
                         std::to_string(size_t(mesh->num_faces()) * 3) + "; the decoded count is used");
    ia.bufferView = appendBuffer(model, std::move(idx));
    ia.byteOffset = 0;
    ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    ia.type = TINYGLTF_TYPE_SCALAR;
    ia.normalized = false;
    ia.count = size_t(mesh->num_faces()) * 3;
    ia.sparse = decltype(ia.sparse){};
    ia.minValues.clear();
    ia.maxValues.clear();
    model.accessors.push_back(ia);
    prim.indices = int(model.accessors.size() - 1);
    prim.extensions.erase("KHR_draco_mesh_compression");
}

/// One EXT_meshopt_compression bufferView decoded into a buffer of its own.
void decodeMeshoptView(tinygltf::Model& model, size_t index, const tinygltf::Value& ext, const std::string& name, const std::string& file) {
    const std::string w = "bufferViews[" + std::to_string(index) + "].extensions." + name;
    const int buffer = intMember(ext, "buffer", -1);
    const int offset = intMember(ext, "byteOffset", 0), length = intMember(ext, "byteLength", -1);
    const int stride = intMember(ext, "byteStride", -1), count = intMember(ext, "count", -1);
    const std::string mode = ext.Has("mode") && ext.Get("mode").IsString() ? ext.Get("mode").Get<std::string>() : "";
    const std::string filter = ext.Has("filter") && ext.Get("filter").IsString() ? ext.Get("filter").Get<std::string>() : "NONE";
    if (buffer < 0 || size_t(buffer) >= model.buffers.size()) throw InputError(file, w + ".buffer: no buffer " + std::to_string(buffer));
    const std::vector<unsigned char>& src = model.buffers[size_t(buffer)].data;
    if (offset < 0 || length < 0 || size_t(offset) > src.size() || size_t(length) > src.size() - size_t(offset))
        throw InputError(file, w + ": bytes " + std::to_string(offset) + "+" + std::to_string(length) + " run past the end of buffer " +
                                   std::to_string(buffer) + " (" + std::to_string(src.size()) + " bytes)");
    if (stride <= 0 || stride > 256 || count < 0 || uint64_t(count) > Limits::kMaxAccessorCount)
        throw InputError(file, w + ": byteStride " + std::to_string(stride) + " or count " + std::to_string(count) + " out of range");
    std::vector<unsigned char> out(size_t(count) * size_t(stride));
    const unsigned char* data = src.data() + offset;
    int rc = -1;
    if (mode == "ATTRIBUTES") {
        if (stride % 4 != 0) throw InputError(file, w + ": ATTRIBUTES need a byteStride that is a multiple of 4");
        rc = meshopt_decodeVertexBuffer(out.data(), size_t(count), size_t(stride), data, size_t(length));
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4) throw InputError(file, w + ": " + mode + " need a byteStride of 2 or 4");
        if (mode == "TRIANGLES" && count % 3 != 0) throw InputError(file, w + ": TRIANGLES need a count divisible by 3");
        rc = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), size_t(count), size_t(stride), data, size_t(length))
                                 : meshopt_decodeIndexSequence(out.data(), size_t(count), size_t(stride), data, size_t(length));
    } else {
        throw InputError(file, w + ".mode: \"" + mode + "\" is not ATTRIBUTES, TRIANGLES or INDICES");
    }
    if (rc != 0) throw InputError(file, w + ": cannot decode the meshopt " + mode + " stream (error " + std::to_string(rc) + ": bad header or truncated data)");
    if (filter == "OCTAHEDRAL") {
        if (stride != 4 && stride != 8) throw InputError(file, w + ": the OCTAHEDRAL filter needs a byteStride of 4 or 8");
        meshopt_decodeFilterOct(out.data(), size_t(count), size_t(stride));
    } else if (filter == "QUATERNION") {
        if (stride != 8) throw InputError(file, w + ": the QUATERNION filter needs a byteStride of 8");
        meshopt_decodeFilterQuat(out.data(), size_t(count), size_t(stride));
    } else if (filter == "EXPONENTIAL") {
        if (stride % 4 != 0) throw InputError(file, w + ": the EXPONENTIAL filter needs a byteStride that is a multiple of 4");
        meshopt_decodeFilterExp(out.data(), size_t(count), size_t(stride));
    } else if (filter != "NONE") {
        throw InputError(file, w + ".filter: \"" + filter + "\" is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    }
    tinygltf::Buffer b;
    b.data = std::move(out);
    model.buffers.push_back(std::move(b));
    tinygltf::BufferView& view = model.bufferViews[index];
    view.buffer = int(model.buffers.size() - 1);
    view.byteOffset = 0;
    view.byteLength = size_t(count) * size_t(stride);
    if (mode == "ATTRIBUTES" && view.byteStride == 0) view.byteStride = size_t(stride);
    view.extensions.erase(name);
}

}  // namespace

void decodeCompressedGeometry(tinygltf::Model& model, const std::string& file, std::vector<std::string>* notes) {
    const size_t views = model.bufferViews.size();
    for (size_t i = 0; i < views; ++i)
        for (const char* name : {"EXT_meshopt_compression", "KHR_meshopt_compression"}) {
            auto it = model.bufferViews[i].extensions.find(name);
            if (it == model.bufferViews[i].extensions.end()) continue;
            const tinygltf::Value ext = it->second;
            decodeMeshoptView(model, i, ext, name, file);
            break;
        }
    for (size_t m = 0; m < model.meshes.size(); ++m)
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            tinygltf::Primitive& prim = model.meshes[m].primitives[p];
            auto it = prim.extensions.find("KHR_draco_mesh_compression");
            if (it == prim.extensions.end()) continue;
            const tinygltf::Value ext = it->second;
            decodeDracoPrimitive(model, prim, ext, "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]", file,
                                 notes);
        }
}

}  // namespace rf::gltf
