#include "engine/load/gltf/gltf_accessors.h"

#include <algorithm>
#include <cstring>

#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_safety.h"

namespace rf::gltf {

namespace {

int componentSize(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;  // includes DOUBLE and INT, which glTF 2.0 does not allow
    }
}

int componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4:
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
        default: return 0;
    }
}

/// One component at p (unaligned), as float; normalized per the glTF 2.0 rules.
float decodeComponent(const unsigned char* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            int8_t v;
            std::memcpy(&v, p, 1);
            return componentValue(v, type, normalized);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return componentValue(*p, type, normalized);
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return componentValue(v, type, normalized);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return componentValue(v, type, normalized);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t v;
            std::memcpy(&v, p, 4);
            return componentValue(v, type, normalized);
        }
        default: {
            float v;
            std::memcpy(&v, p, 4);
            return v;
        }
    }
}

std::string accName(int index) { return "accessors[" + std::to_string(index) + "]"; }

/// Element e of `count` elements at byteOffset within span, stride apart: checks the whole range.
void checkRange(const ByteSpan& span, uint64_t byteOffset, uint64_t count, uint64_t stride, uint64_t elemSize,
                const std::string& file, const std::string& what) {
    if (count == 0) return;
    const uint64_t end = byteOffset + (count - 1) * stride + elemSize;  // count ≤ 2^26, stride ≤ 2^32: no overflow
    if (byteOffset > span.size || end > span.size)
        throw InputError(file, what + ": reads bytes up to " + std::to_string(end) + " of a bufferView of " +
                                   std::to_string(span.size) + " bytes");
}

}  // namespace

ByteSpan bufferViewSpan(const tinygltf::Model& model, int view, const std::string& file) {
    const std::string w = "bufferViews[" + std::to_string(view) + "]";
    if (view < 0 || size_t(view) >= model.bufferViews.size()) throw InputError(file, w + ": no such bufferView");
    const tinygltf::BufferView& bv = model.bufferViews[size_t(view)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= model.buffers.size())
        throw InputError(file, w + ".buffer: no buffer " + std::to_string(bv.buffer));
    const std::vector<unsigned char>& data = model.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        throw InputError(file, w + ": bytes " + std::to_string(bv.byteOffset) + "+" + std::to_string(bv.byteLength) +
                                   " run past the end of buffer " + std::to_string(bv.buffer) + " (" +
                                   std::to_string(data.size()) + " bytes)");
    return ByteSpan{data.data() + bv.byteOffset, bv.byteLength};
}

namespace {

/// Overwrites the elements a sparse accessor names (after the dense bufferView, or zeros).
void applySparse(const tinygltf::Model& model, const tinygltf::Accessor& a, const std::string& w, const std::string& file,
                 AccessorData& out) {
    const int csize = componentSize(a.componentType);
    const int comps = out.components;
    const uint64_t elemSize = uint64_t(csize) * comps;
    const std::string ws = w + ".sparse";
    if (a.sparse.count < 0 || size_t(a.sparse.count) > a.count)
        throw InputError(file, ws + ".count: " + std::to_string(a.sparse.count) + " outside [0, " + std::to_string(a.count) + "]");
    const uint64_t n = uint64_t(a.sparse.count);
    const int itype = a.sparse.indices.componentType;
    if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        throw InputError(file, ws + ".indices.componentType: expected an unsigned integer type");
    if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0) throw InputError(file, ws + ": negative byteOffset");
    const ByteSpan ispan = bufferViewSpan(model, a.sparse.indices.bufferView, file);
    const ByteSpan vspan = bufferViewSpan(model, a.sparse.values.bufferView, file);
    const int isize = componentSize(itype);
    checkRange(ispan, uint64_t(a.sparse.indices.byteOffset), n, isize, isize, file, ws + ".indices");
    checkRange(vspan, uint64_t(a.sparse.values.byteOffset), n, elemSize, elemSize, file, ws + ".values");
    const unsigned char* ip = ispan.data + a.sparse.indices.byteOffset;
    const unsigned char* vp = vspan.data + a.sparse.values.byteOffset;
    for (uint64_t k = 0; k < n; ++k) {
        // Integer decode: indices above 2^24 would not survive a trip through float.
        uint32_t target = 0;
        std::memcpy(&target, ip + k * isize, size_t(isize));  // little-endian: low bytes first
        if (target >= a.count)
            throw InputError(file, ws + ".indices[" + std::to_string(k) + "]: index outside the accessor's " + std::to_string(a.count) + " elements");
        for (int c = 0; c < comps; ++c)
            out.values[target * comps + c] = decodeComponent(vp + k * elemSize + size_t(c) * csize, a.componentType, a.normalized);
    }
}

}  // namespace

AccessorData readAccessor(const tinygltf::Model& model, int index, const std::string& file, const std::vector<int>& types) {
    const std::string w = accName(index);
    if (index < 0 || size_t(index) >= model.accessors.size()) throw InputError(file, w + ": no such accessor");
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    const int csize = componentSize(a.componentType);
    const int comps = componentCount(a.type);
    if (csize == 0) throw InputError(file, w + ".componentType: " + std::to_string(a.componentType) + " is not a glTF 2.0 component type");
    if (comps == 0) throw InputError(file, w + ".type: not a glTF 2.0 accessor type");
    if (!types.empty() && std::find(types.begin(), types.end(), a.type) == types.end())
        throw InputError(file, w + ".type: wrong type for this use");
    if (a.count > Limits::kMaxAccessorCount)
        throw InputError(file, w + ".count: " + std::to_string(a.count) + " is over the limit of " + std::to_string(Limits::kMaxAccessorCount));
    if (a.bufferView < 0 && a.count > Limits::kMaxViewlessCount)
        throw InputError(file, w + ".count: " + std::to_string(a.count) + " elements without a bufferView is over the limit of " +
                                   std::to_string(Limits::kMaxViewlessCount));
    if (comps > 4 && csize < 4) throw InputError(file, w + ": padded 8/16-bit matrices are not supported");

    AccessorData out;
    out.components = comps;
    out.count = a.count;
    out.values.assign(a.count * comps, 0.f);
    const uint64_t elemSize = uint64_t(csize) * comps;
    if (a.bufferView >= 0) {
        const ByteSpan span = bufferViewSpan(model, a.bufferView, file);
        const uint64_t viewStride = model.bufferViews[size_t(a.bufferView)].byteStride;
        const uint64_t stride = viewStride ? viewStride : elemSize;
        if (stride < elemSize) throw InputError(file, w + ": bufferView byteStride " + std::to_string(stride) + " is smaller than the element (" + std::to_string(elemSize) + " bytes)");
        checkRange(span, a.byteOffset, a.count, stride, elemSize, file, w);
        const unsigned char* base = span.data + a.byteOffset;
        float* dst = out.values.data();
        for (size_t e = 0; e < a.count; ++e, base += stride)
            for (int c = 0; c < comps; ++c) *dst++ = decodeComponent(base + size_t(c) * csize, a.componentType, a.normalized);
    }

    if (a.sparse.isSparse) applySparse(model, a, w, file, out);
    return out;
}

std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& file) {
    const std::string w = accName(index);
    if (index < 0 || size_t(index) >= model.accessors.size()) throw InputError(file, w + ": no such accessor");
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        throw InputError(file, w + ": indices must be unsigned byte, short or int");
    if (a.normalized) throw InputError(file, w + ": indices must not be normalized");
    // Floats represent unsigned ints exactly only below 2^24; read 32-bit indices directly.
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && !a.sparse.isSparse && a.bufferView >= 0) {
        if (a.type != TINYGLTF_TYPE_SCALAR) throw InputError(file, w + ".type: indices must be SCALAR");
        if (a.count > Limits::kMaxAccessorCount) throw InputError(file, w + ".count: over the limit");
        const ByteSpan span = bufferViewSpan(model, a.bufferView, file);
        const uint64_t viewStride = model.bufferViews[size_t(a.bufferView)].byteStride;
        const uint64_t stride = viewStride ? viewStride : 4;
        if (stride < 4) throw InputError(file, w + ": byteStride smaller than an index");
        checkRange(span, a.byteOffset, a.count, stride, 4, file, w);
        std::vector<uint32_t> out(a.count);
        for (size_t i = 0; i < a.count; ++i) std::memcpy(&out[i], span.data + a.byteOffset + i * stride, 4);
        return out;
    }
    const AccessorData d = readAccessor(model, index, file, {TINYGLTF_TYPE_SCALAR});
    std::vector<uint32_t> out(d.count);
    for (size_t i = 0; i < d.count; ++i) out[i] = static_cast<uint32_t>(d.values[i]);
    return out;
}

float componentValue(double stored, int componentType, bool normalized) {
    if (!normalized) return float(stored);
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return std::max(float(stored) / 127.f, -1.f);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return float(stored) / 255.f;
        case TINYGLTF_COMPONENT_TYPE_SHORT: return std::max(float(stored) / 32767.f, -1.f);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return float(stored) / 65535.f;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return float(stored / 4294967295.0);
        default: return float(stored);
    }
}

}  // namespace rf::gltf
