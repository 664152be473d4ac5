#include "engine/load/gltf/gltf_loader.h"

#include <glm/gtc/matrix_transform.hpp>
#include <tiny_gltf.h>

#include "engine/scene/default_rig.h"
#include "engine/scene/env_lighting.h"
#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_model.h"
#include "engine/geometry/render_origin.h"

namespace rf {

using gltf::GltfModel;

size_t loadGltfModel(Scene& scene, const std::string& path, const DMat4& worldFromModel, FileSource& fs, int materialOverride,
                     const AssetOptions& assets) {
    GltfModel model(path, fs, assets);
    model.addTo(scene, worldFromModel, materialOverride);
    return model.variantCount();
}

size_t loadGltfModel(Scene& scene, const std::string& path, tinygltf::Model parsed, std::vector<std::string> notes,
                     const DMat4& worldFromModel, int materialOverride, const AssetOptions& assets) {
    GltfModel model(path, std::move(parsed), std::move(notes), assets);
    model.addTo(scene, worldFromModel, materialOverride);
    return model.variantCount();
}

namespace {
Scene sceneOf(GltfModel& model, const std::string& path, FileSource& fs, const SceneOptions& options);
}  // namespace

Scene loadGltfScene(const std::string& path, FileSource& fs, const SceneOptions& options) {
    GltfModel model(path, fs, options.assets);
    return sceneOf(model, path, fs, options);
}

Scene loadGltfScene(const std::string& path, tinygltf::Model parsed, std::vector<std::string> notes, FileSource& fs,
                    const SceneOptions& options) {
    GltfModel model(path, std::move(parsed), std::move(notes), options.assets);
    return sceneOf(model, path, fs, options);
}

namespace {
Scene sceneOf(GltfModel& model, const std::string& path, FileSource& fs, const SceneOptions& options) {
    Scene s;
    s.sourcePath = path;
    applyRenderSize(options, s.settings);
    glm::dvec3 lo, hi;
    if (!model.bounds(DMat4(1.0), lo, hi)) throw InputError(path, model.emptyReason());
    if (options.inputsRead) {
        // The environment image is the one input still unread; read it now (it stays cached in
        // fs) so every file is in hand before the meshes, BVH and environment maps are built.
        if (options.environment && !options.environment->file.empty()) fs.read(options.environment->file, kMaxEnvironmentBytes);
        options.inputsRead();
    }
    const glm::dvec3 center = 0.5 * (lo + hi);
    s.renderOrigin = chooseRenderOrigin(center);
    model.addTo(s, DMat4(1.0));
    model.releaseLoadData();  // the scene holds all it needs now; the build below is the peak
    const float radius = float(0.5 * glm::length(hi - lo));
    const float aspect = float(s.settings.width) / float(s.settings.height);
    s.camera = frameBoundingSphere(Vec3(center - s.renderOrigin), radius > 0.f ? radius : 1.f, aspect);
    // A bare model (no lights of its own, no environment asked for) stands in the built-in
    // studio with one key light for crisp shadows; a model with its own lights gets a black
    // world, as Blender gives it. An environment given for a model without lights is its whole
    // light, as in Blender: a key light on top would light what the environment leaves in shade
    // (a backdrop facing away from the sky came out near white).
    SceneOptions opts = options;
    if (s.lights.empty() && !opts.environment) {
        addDefaultKeyLight(s, s.camera);
        opts.environment = EnvironmentSpec{};
    }
    s.background = Color(0.f);
    // glTF's light units are photometric and its models carry no exposure: meter one for the
    // film, and roll highlights off as the glTF Sample Viewer does.
    s.settings.autoExposure = true;
    s.settings.toneMap = ToneMap::PbrNeutral;
    // 2×2 stratified samples: at one, thin parallel edges (2CylinderEngine's fins) alias into a
    // moiré that crawls as the model turns. `rayfarm report` on that film put 4 spp at +6 dB
    // (31.4 → 37.5 dB against 64 spp) for 3.2× the time; 9 spp buys +5 dB more for 2.7× again.
    s.settings.spp = 4;
    attachEnvironment(s, std::nullopt, opts, fs);
    if (options.buildAccel) s.build();
    return s;
}
}  // namespace

const Camera& chosenGltfCamera(const Scene& scene, int index) {
    if (index < 0 || size_t(index) >= scene.gltfCameras.size())
        throw InputError(scene.sourcePath, "no glTF camera " + std::to_string(index) + " (the scene has " +
                                               std::to_string(scene.gltfCameras.size()) + ")");
    // Named as the file names it: "model.gltf: cameras[2].perspective.yfov 0 is not ...".
    if (size_t(index) < scene.gltfCameraFaults.size() && !scene.gltfCameraFaults[size_t(index)].second.empty()) {
        const auto& [file, fault] = scene.gltfCameraFaults[size_t(index)];
        throw InputError(file, fault + "; choose another --camera");
    }
    return scene.gltfCameras[size_t(index)];
}

void useGltfCamera(Scene& scene, int index) { scene.camera = chosenGltfCamera(scene, index); }

}  // namespace rf
