#pragma once
/// EXT_mesh_gpu_instancing: a node whose mesh is drawn once per instance, each placed by its own
/// TRANSLATION, ROTATION and SCALE (accessors of one count) inside the node's space.
///
/// Today the instances of a primitive are written out into one mesh in the node's space (the
/// primitive's vertices once per instance), so the rest of the loader and the renderer treat it
/// as any other node's mesh: static, rigidly animated or morphed. Memory grows with instances ×
/// vertices; Limits::kMaxTriangles counts every instance. Storing a mesh once for all its
/// instances (a shared bottom-level tree) is issue 42's item 3, not yet done.
#include <cstdint>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "engine/geometry/mesh.h"
#include "engine/util/vec_math.h"

namespace rf::gltf {

/// How many instances node draws its mesh as: the extension's accessor count (checked against
/// the accessors, not read), or 1 without the extension. For the size cap, before anything is read.
uint64_t gpuInstanceCount(const tinygltf::Model& model, int node);

/// One instance: TRANSLATION, ROTATION (x, y, z, w; unit length) and SCALE as stored (40
/// bytes, where a matrix would take 128: a million instances are read before anything is drawn).
struct InstanceTrs {
    float t[3] = {0.f, 0.f, 0.f};
    float r[4] = {0.f, 0.f, 0.f, 1.f};
    float s[3] = {1.f, 1.f, 1.f};
    /// node-from-instance: T·R·S.
    DMat4 matrix() const;
};

/// The node's instances, in order (a missing attribute is the identity). present false: the
/// node has no EXT_mesh_gpu_instancing. Throws InputError naming the node and attribute when
/// the extension is malformed: no attributes, an attribute that is not an accessor, of the
/// wrong type or component type, counts that differ, a non-finite value, a zero quaternion.
/// Attributes beyond the three (an application's "_ID") only give the count.
struct GpuInstances {
    bool present = false;
    std::vector<InstanceTrs> instances;
};
GpuInstances readGpuInstances(const tinygltf::Model& model, int node, const std::string& file);

/// The primitive g once per instance, in the node's space: positions and their morph offsets by
/// the instance's matrix, normals and tangents by its linear part (normals by the inverse
/// transpose), a mirroring instance's triangles turned back to counter-clockwise. An instance
/// with a zero scale is left out (counted in unplaced).
TriangleMesh instancedPrimitive(const TriangleMesh& g, const std::vector<InstanceTrs>& instances, size_t& unplaced);

}  // namespace rf::gltf
