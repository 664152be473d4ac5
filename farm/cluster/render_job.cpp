#include "farm/cluster/render_job.h"

#include <cstring>
#include <filesystem>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "farm/cluster/chunk_workshop.h"


namespace rf::farm {

std::string RenderJob::identity() const {
    nlohmann::ordered_json j;
    std::error_code ec;
    const auto abs = std::filesystem::weakly_canonical(scenePath, ec);
    j["scene"] = ec ? scenePath : abs.string();
    j["width"] = settings.width;
    j["height"] = settings.height;
    j["spp"] = settings.spp;
    j["depth"] = settings.maxDepth;
    j["min_weight"] = settings.minWeight;
    j["tonemap"] = settings.toneMap == ToneMap::Clamp ? "clamp" : settings.toneMap == ToneMap::Reinhard ? "reinhard" : "pbr-neutral";
    j["exposure"] = settings.exposure;
    j["timeline_frames"] = timelineFrames;
    j["timeline_fps"] = timelineFps;
    // Only when asked for, so frames directories written before these options still resume.
    if (background.kind == BackgroundChoice::Transparent) j["background"] = "transparent";
    if (background.kind == BackgroundChoice::Colour) {
        j["background"] = {background.r, background.g, background.b};
        // Since issue 47 the colour is shown exactly, not exposed: frames kept from before differ.
        j["background_shown"] = "exact";
    }
    if (exrFrames) j["frames_format"] = "exr";
    if (settings.indirectSamples > 0) j["indirect"] = settings.indirectSamples;
    // Frames kept before bounce light were rendered without it: they do not resume into a film with it.
    j["bounce"] = settings.bounce;
    if (settings.bounceMoving) j["bounce_moving"] = true;
    if (settings.shading != ShadingModel::Phong) j["shading"] = "blinn-phong";
    // Not here, as they change no pixel: tileSize, packets and blockerCache (speed-ups shown
    // bit-exact by the tests), autoExposure (resolved into exposure above), integrator (one kind).
    // The scene options of the command line, over the scene file's own (whose bytes are in the
    // manifest's input digests).
    const SceneOptions& o = sceneOptions;
    if (o.environment) {
        const auto env = std::filesystem::weakly_canonical(o.environment->file, ec);
        j["environment"] = ec ? o.environment->file : env.string();
    }
    if (o.environmentRotation) j["environment_rotation"] = *o.environmentRotation;
    if (o.environmentIntensity) j["environment_intensity"] = *o.environmentIntensity;
    if (o.ground) j["ground"] = *o.ground == Ground::Shadow ? "shadow" : "none";
    if (o.animation) j["animation"] = *o.animation;
    if (o.camera) j["camera"] = *o.camera;
    if (o.assets.scene >= 0) j["gltf_scene"] = o.assets.scene;
    if (!o.assets.variant.empty()) j["variant"] = o.assets.variant;
    if (o.assets.maxTextureSize != AssetOptions{}.maxTextureSize) j["max_texture_size"] = o.assets.maxTextureSize;
    if (o.assets.pointSize != AssetOptions{}.pointSize) j["point_size"] = o.assets.pointSize;
    return j.dump();
}

ChunkVideoSpec chunkVideoSpec(const RenderJob& j) {
    ChunkVideoSpec v;
    v.path = j.output;
    v.width = j.settings.width;
    v.height = j.settings.height;
    v.options = j.mp4;
    return v;
}

bool chunksOnRenderers(const RenderJob& j) { return containerFor(j.output) != Container::Gif && !j.exrFrames; }

std::string encodeWorkerJob(const RenderJob& j) {
    // Settings as a byte copy: every rank runs the same executable, and a field added to
    // RenderSettings later travels without anyone remembering to add it here.
    static_assert(std::is_trivially_copyable_v<RenderSettings>);
    static_assert(std::is_trivially_copyable_v<WorkerOutputs>);
    const WorkerOutputs outputs{j.background, j.exrFrames ? 1 : 0};
    std::string out(reinterpret_cast<const char*>(&j.settings), sizeof(RenderSettings));
    out.append(reinterpret_cast<const char*>(&outputs), sizeof outputs);
    if (j.chunkedFrames) out.append(encodeChunkVideoSpec(chunkVideoSpec(j)));
    return out;
}

RenderSettings decodeWorkerJob(const std::string& bytes, WorkerOutputs* outputs, std::string* chunkVideo) {
    constexpr size_t fixed = sizeof(RenderSettings) + sizeof(WorkerOutputs);
    if (bytes.size() < fixed) throw std::runtime_error("malformed job broadcast");
    RenderSettings s;
    std::memcpy(&s, bytes.data(), sizeof s);
    WorkerOutputs o;
    std::memcpy(&o, bytes.data() + sizeof s, sizeof o);
    if (outputs) *outputs = o;
    if (chunkVideo) *chunkVideo = bytes.substr(fixed);
    return s;
}

}  // namespace rf::farm
