#pragma once
/// What the command line adds to a scene as it loads, the same on every rank.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "engine/util/settings.h"

namespace rf {

/// An environment light: a file, or the built-in studio when file is empty.
struct EnvironmentSpec {
    std::string file;
    float rotationDeg = 0.f;  ///< about +Y
    float intensity = 1.f;
};

/// What `--ground` (the scene file's "ground") puts under the model.
enum class Ground {
    None,
    Shadow,  ///< an invisible shadow catcher at the bottom of the bounds (shadow_catcher.h)
};

/// Where a glTF model's files may come from, and what its textures may cost (gltf_images.h).
struct AssetOptions {
    /// Relative URIs may leave the model's folder but not this folder (--asset-root, the scene
    /// file's "asset_root"). Empty: the current directory when the model lies under it, else the
    /// model's own folder.
    std::string root;
    /// Textures wider or taller than this are downsampled on load (--max-texture-size).
    int maxTextureSize = 8192;
    /// Decoded texels (and their mip-maps) of all of a scene's textures together; a texture that
    /// would go over is refused (the load fails, saying so).
    uint64_t textureBudgetBytes = 6ull << 30;
    /// KHR_materials_variants: the variant to show ("": the file's own materials), and what
    /// chose it, for messages ("--variant", "objects[2].variant"). variantRequired: a file
    /// without variants is refused; otherwise (--variant over a scene of several models) it
    /// shows its own materials.
    std::string variant;
    std::string variantSource = "--variant";
    bool variantRequired = true;
    /// glTF points and lines (modes 0–3) are drawn this many pixels wide at a bare model's
    /// default framing in a 640×360 picture (a fixed share of the model's size, so a bigger
    /// picture shows them proportionally wider, as it does the rest of the model).
    float pointSize = 1.5f;
    /// --scene N: which of a glTF file's scenes is drawn (-1: the file's "scene", else the
    /// first); sceneSource names what chose it, for messages.
    int scene = -1;
    std::string sceneSource = "--scene";
};

struct SceneOptions {
    std::optional<EnvironmentSpec> environment;  ///< replaces the scene's own
    std::optional<float> environmentRotation;    ///< overrides the rotation of whichever is used
    std::optional<float> environmentIntensity;   ///< overrides its intensity
    /// The render's size (--size; 0: the scene's own). The scene carries it so that a framing
    /// built from the scene (a turntable's auto distance) fits the picture's aspect ratio.
    int width = 0, height = 0;
    std::optional<Ground> ground;  ///< replaces the scene file's "ground"
    /// --animation NAME|INDEX: the model animation to play, over the scene file's choice.
    std::optional<std::string> animation;
    /// --camera N: look through the scene's glTF camera N (Scene::gltfCameras), animated.
    std::optional<int> camera;
    /// Asset root and texture limits; rootFromCommandLine: root came from --asset-root and
    /// overrides a scene file's "asset_root".
    AssetOptions assets;
    bool rootFromCommandLine = false;
    /// false: a model's acceleration structures are not built (`info` traces nothing); the
    /// caller calls Scene::build() before anything walks the geometry. Scene files are always built.
    bool buildAccel = true;
    /// Called once by a loader that has read every input file (the model, its buffers and
    /// images, the environment image) and is about to build from them: rank 0 sends the files
    /// to the other ranks then, so they build their scenes while it builds its own.
    std::function<void()> inputsRead;
};

/// The options' render size over the scene's settings.
inline void applyRenderSize(const SceneOptions& o, RenderSettings& s) {
    if (o.width > 0 && o.height > 0) {
        s.width = o.width;
        s.height = o.height;
    }
}

}  // namespace rf
