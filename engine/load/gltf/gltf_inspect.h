#pragma once
/// What a glTF file holds, as `rayfarm info` describes it (after gltf-transform inspect and
/// gltfpack -v): meshes with their triangles and bounds, materials and the extensions each
/// uses, textures with format and size, animations, skins, cameras, lights, the file's
/// extensions and whether rayfarm supports them, KHR_materials_variants names. Read from the
/// file as written (mesh space, the lights' own units), through the loader's guards.
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}  // namespace tinygltf

#include "engine/util/file_source.h"
#include "engine/scene/scene_options.h"
#include "engine/util/vec_math.h"

namespace rf {

struct GltfInfo {
    struct Mesh {
        std::string name;
        int primitives = 0;
        uint64_t instances = 0;    ///< times the drawn scene draws it: its nodes, each by its EXT_mesh_gpu_instancing count
        uint64_t gpuInstances = 0; ///< of those, drawn through EXT_mesh_gpu_instancing
        uint64_t triangles = 0;    ///< as the file gives them (strips and fans unrolled), before any is dropped
        uint64_t vertices = 0;     ///< POSITION elements over its primitives
        uint64_t points = 0;       ///< POINTS primitives' points (drawn as dots)
        uint64_t lineSegments = 0; ///< LINES, LINE_LOOP and LINE_STRIP primitives' segments (drawn as lines)
        int morphTargets = 0;      ///< most targets of any of its primitives
        bool skinned = false;      ///< some primitive has JOINTS_0/WEIGHTS_0 and some node skins it
        bool hasBounds = false;    ///< false: no triangle has finite positions
        DVec3 min{0.0}, max{0.0};  ///< of its triangles' (points', lines') vertices, in the mesh's own space
    };
    struct Material {
        std::string name;
        std::string alphaMode;     ///< OPAQUE, MASK or BLEND
        bool doubleSided = false;
        std::vector<std::string> extensions;  ///< its own and its textures' (KHR_texture_transform), sorted
    };
    struct Texture {
        std::string name;
        int image = -1;            ///< the image rayfarm draws (EXT_texture_webp's first); -1: none
        std::string format;        ///< by the image's first bytes: png, jpeg, webp, ktx2, bmp, gif; "" unknown
        int width = 0, height = 0; ///< from the header; 0 when unreadable
        std::string source;        ///< "file NAME", "data URI", "bufferView N" or "missing"
    };
    struct Animation {
        std::string name;
        double duration = 0.0;     ///< last key time of its samplers, seconds
        int channels = 0;
        int samplers = 0;
        std::vector<std::string> paths;  ///< the target paths its channels animate, sorted, each once
    };
    struct Skin {
        std::string name;
        int joints = 0;
        bool inverseBindMatrices = false;
    };
    struct Camera {
        std::string name;
        std::string type;          ///< perspective or orthographic
        double yfovDeg = 0.0;      ///< perspective
        double aspect = 0.0;       ///< perspective; 0 when the file leaves it to the viewport
        double znear = 0.0, zfar = 0.0;  ///< zfar 0: infinite
        double xmag = 0.0, ymag = 0.0;   ///< orthographic
    };
    struct Light {
        std::string name;
        std::string type;          ///< point, spot or directional
        double intensity = 1.0;
        std::string unit;          ///< cd (point, spot) or lx (directional)
        DVec3 color{1.0};
        double range = 0.0;        ///< 0: infinite
    };
    struct Extension {
        std::string name;
        bool required = false;
        bool supported = false;    ///< rayfarm renders its effect
    };

    struct SceneEntry {
        std::string name;
        int roots = 0;             ///< the nodes it lists
    };

    std::string generator, version;
    /// The file's format when it is not glTF ("OBJ", "STL", ...: read through assimp and
    /// described as the glTF model it became); "" for glTF.
    std::string format;
    int nodes = 0;
    std::vector<SceneEntry> scenes;
    int defaultScene = -1;         ///< the file's "scene", -1 when it names none
    int drawnScene = -1;           ///< the scene drawn (--scene, else the default, else 0); -1: none
    uint64_t drawnTriangles = 0;   ///< triangles over the drawn scene's mesh instances
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Animation> animations;
    std::vector<Skin> skins;
    std::vector<Camera> cameras;
    std::vector<Light> lights;
    std::vector<Extension> extensions;  ///< extensionsUsed, plus any required but not listed there
    std::vector<std::string> variants;  ///< KHR_materials_variants names, in order
};

/// Reads path through the same guards as the loader; throws InputError naming the file on what
/// the loader would refuse to parse. Geometry is decoded (Draco, meshopt) to give bounds.
GltfInfo inspectGltf(const std::string& path, FileSource& fs, const AssetOptions& assets = {});
/// The same for a model already parsed (or made from another format).
GltfInfo inspectGltf(const std::string& path, const tinygltf::Model& model, const AssetOptions& assets = {});

}  // namespace rf
