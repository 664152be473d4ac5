#pragma once
/// Safe reading of glTF accessors: every accessor is checked against its bufferView and buffer
/// (and a sparse accessor's index and value views) before a byte is read. Handles byteStride,
/// every component type, normalized integers (KHR_mesh_quantization) and sparse substitution.
#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

namespace rf::gltf {

/// Decoded accessor: count elements of `components` floats each, row by row.
struct AccessorData {
    std::vector<float> values;
    int components = 0;
    size_t count = 0;
    float at(size_t element, int component) const { return values[element * components + component]; }
};

/// Validated byte span of a bufferView; throws InputError(file, "bufferViews[i]: …").
struct ByteSpan {
    const unsigned char* data = nullptr;
    size_t size = 0;
};
ByteSpan bufferViewSpan(const tinygltf::Model& model, int view, const std::string& file);

/// Reads accessor `index` as floats. `types` lists the allowed TINYGLTF_TYPE_* values (empty:
/// any). Normalized integers map to [0, 1] or [−1, 1]; others keep their integer value. Throws
/// InputError naming the accessor on any inconsistency.
AccessorData readAccessor(const tinygltf::Model& model, int index, const std::string& file,
                          const std::vector<int>& types = {});

/// A component as readAccessor delivers it, from its stored value (an integer for integer
/// types): normalized integers map to [0, 1] or [−1, 1] per glTF 2.0, the rest are unchanged.
/// Also for what is written in the stored units, as an accessor's min and max are.
float componentValue(double stored, int componentType, bool normalized);

/// Reads an index accessor (SCALAR, unsigned byte/short/int, not normalized).
std::vector<uint32_t> readIndices(const tinygltf::Model& model, int index, const std::string& file);

}  // namespace rf::gltf
