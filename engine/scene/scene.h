#pragma once
/// The scene in render space: its geometry (scene_geometry.h: primitives, the acceleration
/// structure and ray queries), materials, textures, lights, environment and camera. What a
/// scene file says about time travels beside it (engine/load/loaded_scene.h). World
/// position = render position + renderOrigin (kept in double, so a model far from the world
/// origin keeps its float precision).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/geometry/camera.h"
#include "engine/geometry/interaction.h"
#include "engine/lights/light.h"
#include "engine/materials/material.h"
#include "engine/materials/material_eval.h"
#include "engine/materials/texture.h"
#include "engine/scene/scene_geometry.h"
#include "engine/scene/scene_options.h"
#include "engine/util/settings.h"

namespace rf {

class EnvironmentLight;

/// What a scene uses, so the renderer can leave out what it does not need.
struct SceneFeatures {
    bool reflection = false;    ///< some material reflects
    bool transmission = false;  ///< some material refracts
    bool shadows = false;       ///< some light casts shadows
    bool textures = false;      ///< some material samples a texture
    bool animated = false;      ///< some mesh hangs on an animated node
};

class Scene {
public:
    Camera camera;
    std::vector<Light> lights;
    std::vector<Material> materials;
    TextureSet textures;  ///< shared by copies of the scene (texture.h)
    std::vector<Camera> gltfCameras;  ///< glTF models' cameras in node order, selectable as the render camera
    /// Beside each of gltfCameras: its file, and why it cannot be used ("" if it can), said
    /// when it is chosen.
    std::vector<std::pair<std::string, std::string>> gltfCameraFaults;
    /// Beside each of gltfCameras: the model (geometry.models) and node it hangs on, so the
    /// timeline can follow the node's animation.
    struct CameraNode {
        int model = -1, node = -1;
        int camera = -1;  ///< the file's cameras[] entry the node names
    };
    std::vector<CameraNode> gltfCameraNodes;
    Color background{0.f};
    /// Primary rays that miss give no colour and zero coverage (alpha), so the film can be laid
    /// over something else; reflections and refractions still see `background`.
    bool transparentBackground = false;
    /// --background COLOUR: primary rays that miss show `background` exactly in the picture (not
    /// exposed, not tone-mapped; linear in linear frames), as a backdrop; the render keeps the
    /// model's colour premultiplied by its coverage, as for a transparent background, and lays
    /// it over the colour when it encodes. Reflections and refractions see `background` as
    /// radiance. Auto exposure therefore meters the model alone.
    bool exactBackground = false;
    /// Primary rays that miss add nothing to the colour (transparent or exact background).
    bool primaryMissesEmpty() const { return transparentBackground || exactBackground; }
    /// Light from all around, as an equirectangular radiance image (null: none).
    std::shared_ptr<const EnvironmentLight> environment;
    /// What `environment` was made from (file empty: the built-in studio), so a saved scene
    /// file can name it again.
    EnvironmentSpec environmentSource;
    /// Primary rays that miss everything see the environment instead of `background`
    /// (secondary rays see it whenever there is one).
    bool environmentBackground = false;
    /// Render-space height of the shadow catcher of --ground shadow (shadow_catcher.h): camera
    /// rays that reach it see what lies behind it dimmed by the model's shadow. None: no ground.
    std::optional<float> shadowCatcherHeight;
    Color ambientLight{1.f};  ///< I_amb of the seed's model
    RenderSettings settings;  ///< defaults from the scene file; the CLI may override
    DVec3 renderOrigin{0.0};
    std::string sourcePath;
    std::vector<std::string> notes;  ///< warnings met while loading

    /// Spheres, planes, meshes and models, the acceleration structure over them and every ray
    /// query (scene_geometry.h).
    SceneGeometry geometry;

    /// geometry.build() with the materials and textures its masked-triangle test reads: call
    /// after loading, or after geometry or a material's alpha changed.
    void build() { geometry.build(materials, textures); }
    SceneFeatures features() const;
};

/// Base colour of the scene's material at a surface point (material_eval.h's baseColor).
inline Color baseColor(const Scene& scene, const SurfaceInteraction& si, float* alpha = nullptr) {
    return baseColor(scene.materials[si.material], scene.textures, scene.renderOrigin, si, alpha);
}

}  // namespace rf
