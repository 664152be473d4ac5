#include "engine/load/gltf/gltf_inspect.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include <tiny_gltf.h>

#include "engine/load/gltf/gltf_accessors.h"
#include "engine/load/gltf/gltf_instancing.h"
#include "engine/load/gltf/gltf_geometry.h"
#include "engine/load/gltf/gltf_images.h"
#include "engine/load/gltf/gltf_parse.h"
#include "engine/load/gltf/gltf_safety.h"

namespace rf {

namespace {

using namespace gltf;

/// Triangles a primitive describes, from its element count and mode (0 for points and lines).
uint64_t primitiveTriangles(const tinygltf::Model& model, const tinygltf::Primitive& p) {
    int acc = p.indices;
    if (acc < 0)
        if (auto it = p.attributes.find("POSITION"); it != p.attributes.end()) acc = it->second;
    if (acc < 0 || size_t(acc) >= model.accessors.size()) return 0;
    const uint64_t n = model.accessors[size_t(acc)].count;
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode == TINYGLTF_MODE_TRIANGLES) return n / 3;
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN) return n >= 3 ? n - 2 : 0;
    return 0;
}

/// How many times each mesh is drawn: nodes of scene sc (every root without one), each as many
/// times as its EXT_mesh_gpu_instancing has instances (counted in gpu as well).
std::vector<uint64_t> meshInstances(const tinygltf::Model& model, int sc, std::vector<uint64_t>& gpu) {
    std::vector<uint64_t> count(model.meshes.size(), 0);
    gpu.assign(model.meshes.size(), 0);
    std::vector<int> stack;
    if (sc >= 0 && size_t(sc) < model.scenes.size()) {
        stack = model.scenes[size_t(sc)].nodes;
    } else {
        std::vector<uint8_t> child(model.nodes.size(), 0);
        for (const tinygltf::Node& n : model.nodes)
            for (int c : n.children)
                if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = 1;
        for (size_t i = 0; i < model.nodes.size(); ++i)
            if (!child[i]) stack.push_back(int(i));
    }
    std::vector<uint8_t> seen(model.nodes.size(), 0);  // each node once, whatever the file claims
    while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        if (i < 0 || size_t(i) >= model.nodes.size() || seen[size_t(i)]) continue;
        seen[size_t(i)] = 1;
        const tinygltf::Node& n = model.nodes[size_t(i)];
        if (n.mesh >= 0 && size_t(n.mesh) < count.size()) {
            const uint64_t times = gpuInstanceCount(model, i);
            count[size_t(n.mesh)] += times;
            if (n.extensions.count("EXT_mesh_gpu_instancing")) gpu[size_t(n.mesh)] += times;
        }
        stack.insert(stack.end(), n.children.begin(), n.children.end());
    }
    return count;
}

void addExtensions(const tinygltf::ExtensionMap& ext, std::set<std::string>& out) {
    for (const auto& [name, value] : ext) out.insert(name);
}

GltfInfo::Mesh meshInfo(const tinygltf::Model& model, int index, const std::string& path, const std::vector<uint8_t>& skinnedMesh) {
    const tinygltf::Mesh& gm = model.meshes[size_t(index)];
    GltfInfo::Mesh m;
    m.name = gm.name;
    m.primitives = int(gm.primitives.size());
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (size_t p = 0; p < gm.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = gm.primitives[p];
        m.triangles += primitiveTriangles(model, prim);
        if (auto it = prim.attributes.find("POSITION"); it != prim.attributes.end() && it->second >= 0 &&
                                                           size_t(it->second) < model.accessors.size())
            m.vertices += model.accessors[size_t(it->second)].count;
        m.morphTargets = std::max(m.morphTargets, int(prim.targets.size()));
        PrimitiveGeometry g;
        if (!buildPrimitive(model, index, int(p), path, g, false)) continue;  // nothing to draw
        if (g.mesh.influences > 0 && skinnedMesh[size_t(index)]) m.skinned = true;
        if (g.wire && g.wireSegments.empty() && prim.mode == TINYGLTF_MODE_POINTS) m.points += g.wirePoints.size();
        m.lineSegments += g.wireSegments.size() / 2;
        for (uint32_t i : g.wire ? g.wirePoints : g.mesh.indices) {
            const glm::dvec3 q(g.mesh.positions[i]);
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
    }
    m.hasBounds = std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z);
    if (m.hasBounds) m.min = lo, m.max = hi;
    return m;
}

GltfInfo::Material materialInfo(const tinygltf::Material& gm) {
    GltfInfo::Material m;
    m.name = gm.name;
    m.alphaMode = gm.alphaMode.empty() ? "OPAQUE" : gm.alphaMode;
    m.doubleSided = gm.doubleSided;
    std::set<std::string> ext;
    addExtensions(gm.extensions, ext);
    addExtensions(gm.pbrMetallicRoughness.baseColorTexture.extensions, ext);
    addExtensions(gm.pbrMetallicRoughness.metallicRoughnessTexture.extensions, ext);
    addExtensions(gm.normalTexture.extensions, ext);
    addExtensions(gm.occlusionTexture.extensions, ext);
    addExtensions(gm.emissiveTexture.extensions, ext);
    m.extensions.assign(ext.begin(), ext.end());
    return m;
}

GltfInfo::Texture textureInfo(const tinygltf::Model& model, const tinygltf::Texture& gt, const std::string& path) {
    GltfInfo::Texture t;
    t.name = gt.name;
    auto usable = [&](int i) { return i >= 0 && size_t(i) < model.images.size(); };
    if (auto it = gt.extensions.find("EXT_texture_webp"); it != gt.extensions.end() && it->second.Has("source") &&
                                                          it->second.Get("source").IsInt() && usable(it->second.Get("source").Get<int>()))
        t.image = it->second.Get("source").Get<int>();
    else if (usable(gt.source))
        t.image = gt.source;
    if (t.image < 0) {
        t.source = "missing";
        return t;
    }
    const tinygltf::Image& gi = model.images[size_t(t.image)];
    ByteSpan bytes;
    if (gi.bufferView >= 0) {
        t.source = "bufferView " + std::to_string(gi.bufferView);
        try {
            bytes = bufferViewSpan(model, gi.bufferView, path);
        } catch (const std::exception&) {
            bytes = ByteSpan{};  // reported as a texture of unknown format, as the loader notes it
        }
    } else {
        // tinygltf decodes a data URI itself and keeps no URI for it: bytes without a name.
        const bool kept = gi.width == -1 && !gi.image.empty();  // kept encoded by the parser
        t.source = gi.uri.rfind("data:", 0) == 0 || (gi.uri.empty() && kept) ? "data URI" : gi.uri.empty() ? "missing" : "file " + gi.uri;
        if (kept) bytes = ByteSpan{gi.image.data(), gi.image.size()};
    }
    if (bytes.data && bytes.size) {
        ImageHeader h;
        std::string why;
        if (readImageHeader(bytes.data, bytes.size, h, why)) t.width = h.width, t.height = h.height;
        if (h.format != ImageFormat::Unknown)
            for (const char* c = formatName(h.format); *c; ++c) t.format += char(std::tolower(static_cast<unsigned char>(*c)));
    }
    return t;
}

GltfInfo::Animation animationInfo(const tinygltf::Model& model, const tinygltf::Animation& ga, const std::string& path) {
    GltfInfo::Animation a;
    a.name = ga.name;
    a.channels = int(ga.channels.size());
    a.samplers = int(ga.samplers.size());
    std::set<std::string> paths;
    for (const tinygltf::AnimationChannel& c : ga.channels) {
        // KHR_animation_pointer: the JSON pointer it animates ("/cameras/0/perspective/yfov").
        auto ext = c.target_extensions.find("KHR_animation_pointer");
        if (c.target_path == "pointer" && ext != c.target_extensions.end() && ext->second.Has("pointer") &&
            ext->second.Get("pointer").IsString())
            paths.insert(ext->second.Get("pointer").Get<std::string>());
        else
            paths.insert(c.target_path);
    }
    a.paths.assign(paths.begin(), paths.end());
    for (const tinygltf::AnimationSampler& s : ga.samplers) {
        const AccessorData in = readAccessor(model, s.input, path, {TINYGLTF_TYPE_SCALAR});
        for (float t : in.values)
            if (std::isfinite(t)) a.duration = std::max(a.duration, double(t));
    }
    return a;
}

GltfInfo::Camera cameraInfo(const tinygltf::Camera& gc) {
    GltfInfo::Camera c;
    c.name = gc.name;
    c.type = gc.type;
    if (gc.type == "perspective") {
        c.yfovDeg = gc.perspective.yfov * 180.0 / M_PI;
        c.aspect = gc.perspective.aspectRatio;
        c.znear = gc.perspective.znear;
        c.zfar = gc.perspective.zfar;
    } else {
        c.xmag = gc.orthographic.xmag;
        c.ymag = gc.orthographic.ymag;
        c.znear = gc.orthographic.znear;
        c.zfar = gc.orthographic.zfar;
    }
    return c;
}

GltfInfo::Light lightInfo(const tinygltf::Light& gl) {
    GltfInfo::Light l;
    l.name = gl.name;
    l.type = gl.type;
    l.intensity = gl.intensity;
    l.unit = gl.type == "directional" ? "lx" : "cd";  // KHR_lights_punctual's photometric units
    if (gl.color.size() == 3) l.color = DVec3(gl.color[0], gl.color[1], gl.color[2]);
    l.range = gl.range;
    return l;
}

}  // namespace

GltfInfo inspectGltf(const std::string& path, FileSource& fs, const AssetOptions& assets) {
    std::vector<std::string> notes;
    return inspectGltf(path, parseGltf(path, fs, assets, notes), assets);
}

GltfInfo inspectGltf(const std::string& path, const tinygltf::Model& model, const AssetOptions& assets) {
    GltfInfo info;
    info.generator = model.asset.generator;
    info.version = model.asset.version;
    info.nodes = int(model.nodes.size());
    std::vector<uint8_t> skinnedMesh(model.meshes.size(), 0);
    for (const tinygltf::Node& n : model.nodes)
        if (n.skin >= 0 && n.mesh >= 0 && size_t(n.mesh) < skinnedMesh.size()) skinnedMesh[size_t(n.mesh)] = 1;
    for (const tinygltf::Scene& s : model.scenes) info.scenes.push_back({s.name, int(s.nodes.size())});
    info.defaultScene = model.defaultScene;
    info.drawnScene = assets.scene >= 0 ? assets.scene : model.defaultScene >= 0 ? model.defaultScene : model.scenes.empty() ? -1 : 0;
    std::vector<uint64_t> gpu;
    const std::vector<uint64_t> instances = meshInstances(model, info.drawnScene, gpu);
    for (size_t i = 0; i < model.meshes.size(); ++i) {
        info.meshes.push_back(meshInfo(model, int(i), path, skinnedMesh));
        info.meshes.back().instances = instances[i];
        info.meshes.back().gpuInstances = gpu[i];
        info.drawnTriangles += instances[i] * info.meshes.back().triangles;
    }
    for (const tinygltf::Material& m : model.materials) info.materials.push_back(materialInfo(m));
    for (const tinygltf::Texture& t : model.textures) info.textures.push_back(textureInfo(model, t, path));
    for (const tinygltf::Animation& a : model.animations) info.animations.push_back(animationInfo(model, a, path));
    for (const tinygltf::Skin& s : model.skins) info.skins.push_back({s.name, int(s.joints.size()), s.inverseBindMatrices >= 0});
    for (const tinygltf::Camera& c : model.cameras) info.cameras.push_back(cameraInfo(c));
    for (const tinygltf::Light& l : model.lights) info.lights.push_back(lightInfo(l));
    std::vector<std::string> names = model.extensionsUsed;
    for (const std::string& r : model.extensionsRequired)
        if (std::find(names.begin(), names.end(), r) == names.end()) names.push_back(r);
    for (const std::string& e : names) {
        const bool required = std::find(model.extensionsRequired.begin(), model.extensionsRequired.end(), e) != model.extensionsRequired.end();
        info.extensions.push_back({e, required, isSupportedExtension(e)});
    }
    if (auto it = model.extensions.find("KHR_materials_variants"); it != model.extensions.end() && it->second.Has("variants")) {
        const tinygltf::Value& vs = it->second.Get("variants");
        for (size_t i = 0; vs.IsArray() && i < vs.ArrayLen(); ++i) {
            const tinygltf::Value& v = vs.Get(int(i));
            info.variants.push_back(v.Has("name") && v.Get("name").IsString() ? v.Get("name").Get<std::string>() : std::string());
        }
    }
    return info;
}

}  // namespace rf
