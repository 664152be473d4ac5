// rayfarm info: what a glTF file holds and the default turntable rayfarm would make of it, as
// text or JSON (after gltf-transform inspect and gltfpack -v).
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "farm/cli/cli.h"
#include "farm/commands/commands.h"
#include "engine/util/errors.h"
#include "engine/load/gltf/gltf_inspect.h"
#include "engine/util/model_path.h"
#include "engine/load/model_inspect.h"
#include "engine/load/scene_loader.h"
#include "anim/gltf_animation.h"
#include "anim/timeline.h"

namespace rf::cli {

namespace {

using json = nlohmann::ordered_json;

const char* kInfoHelp =
    "usage: rayfarm info MODEL [options]\n"
    "\n"
    "Describes a glTF model (.gltf/.glb), or an OBJ, STL, PLY, FBX, COLLADA (.dae) or 3MF model\n"
    "as the glTF model rayfarm reads it as: meshes (triangles, bounds), materials and their\n"
    "extensions, textures (format, size), animations, skins, cameras, lights (type, intensity,\n"
    "unit), the file's extensions and whether rayfarm supports them, KHR_materials_variants,\n"
    "and the default turntable `rayfarm render MODEL` would make (frames, size, camera).\n"
    "\n"
    "  --json            print JSON instead of text\n"
    "  --size WxH        the turntable's picture size (default: render's)\n"
    "  --fps N           the turntable's frame rate (default 30)\n"
    "  --animation A     the animation the turntable plays (name, index from 0, or all)\n"
    "  --camera N        describe the film through the file's camera N instead of the turntable\n"
    "  --scene N         the file's scene N (default: the file's \"scene\", else 0)\n"
    "  --asset-root DIR  folder the model's relative URIs may reach beyond its own\n";


/// Shortest decimal that reads back to the same float, as JSON numbers: 0.1f prints as 0.1.
double tidy(double v) {
    if (v == 0.0) return 0.0;  // -0 too: "-0" reads as a mistake
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return std::strtod(buf, nullptr);
}
json vec3f(const DVec3& v) { return json::array({tidy(v.x), tidy(v.y), tidy(v.z)}); }

/// The default turntable of the model: what Timeline::fromScene makes of the loaded scene.
json turntableJson(Scene& loaded, const anim::Timeline& tl, size_t fileLights) {
    anim::TrialPose trial(loaded, tl);  // a model that does not move is not copied
    Scene& scene = trial.scene();
    tl.applyFrame(scene, 0);
    const DVec3 eye(scene.camera.eye), target(scene.camera.target);
    const DVec3 d = eye - target;
    const double dist = glm::length(d);
    json t;
    t["through"] = tl.fileCamera() ? json(*tl.fileCamera()) : json("turntable");
    t["frames"] = tl.frameCount();
    t["fps"] = tl.fps();
    t["seconds"] = tl.frameCount() / tl.fps();
    t["width"] = scene.settings.width;
    t["height"] = scene.settings.height;
    t["spp"] = scene.settings.spp;
    t["camera"] = {{"target", vec3f(target + scene.renderOrigin)},
                   {"distance", tidy(dist)},
                   {"elevation_deg", tidy(dist > 0.0 ? glm::degrees(std::asin(std::clamp(d.y / dist, -1.0, 1.0))) : 0.0)},
                   {"fov_deg", tidy(scene.camera.fovDeg)}};
    json clips = json::array();
    // A film through an animated camera renders both ends of the camera's clip: one play.
    const double filmSeconds = tl.fileCameraPeriod() > 0.0 ? tl.fileCameraPeriod() : tl.frameCount() / tl.fps();
    for (const anim::Timeline::Clip& c : tl.clips()) {
        const Animation& a = loaded.geometry.models[size_t(c.model)].animations[size_t(c.animation)];
        const double plays = c.period > 0.0 ? filmSeconds / c.period : 0.0;
        // Whole when the film ends within half a frame of a play's end (frames are whole, clips
        // need not be).
        const bool whole = plays >= 0.5 && std::abs(filmSeconds - std::round(plays) * c.period) <= 0.5 / tl.fps() + 1e-9;
        clips.push_back({{"index", c.animation},
                         {"name", a.name},
                         {"period_s", tidy(c.period)},
                         {"plays", tidy(plays)},
                         {"whole_plays", static_cast<long long>(whole ? std::round(plays) : std::floor(plays))},
                         {"ends_whole", whole}});
    }
    t["animations"] = clips;
    t["lights"] = fileLights ? "the model's own, on a black world" : "a key light and the built-in studio environment";
    return t;
}

/// The cameras --camera N numbers (Scene::gltfCameras, in node order), each with the animations
/// that move its node or a node above it.
json cameraViewsJson(const Scene& scene) {
    json views = json::array();
    for (size_t i = 0; i < scene.gltfCameraNodes.size(); ++i) {
        const Scene::CameraNode& cn = scene.gltfCameraNodes[i];
        json v = {{"option", i}, {"camera", cn.camera}, {"node", cn.node}};
        json moving = json::array(), lens = json::array();
        if (cn.model >= 0 && size_t(cn.model) < scene.geometry.models.size()) {
            const SceneGraph& g = scene.geometry.models[size_t(cn.model)];
            v["node_name"] = cn.node >= 0 && size_t(cn.node) < g.nodes.size() ? g.nodes[size_t(cn.node)].name : std::string();
            auto entry = [&](int a) {
                return json{{"index", a}, {"name", g.animations[size_t(a)].name}, {"duration_s", tidy(g.animations[size_t(a)].duration())}};
            };
            for (int a : anim::animationsMoving(g, cn.node)) moving.push_back(entry(a));
            for (int a : anim::animationsKeyingLens(g, cn.camera)) lens.push_back(entry(a));
        }
        v["animated"] = !moving.empty();
        v["animations"] = moving;
        v["lens_animations"] = lens;  // KHR_animation_pointer keys of its yfov or magnification
        const std::string& fault = i < scene.gltfCameraFaults.size() ? scene.gltfCameraFaults[i].second : std::string();
        v["usable"] = fault.empty();
        views.push_back(v);
    }
    return views;
}

json infoJson(const std::string& path, const GltfInfo& info, const json& turntable, const json& views) {
    json j;
    j["file"] = path;
    if (!info.format.empty()) j["format"] = info.format;  // read through assimp as this glTF model
    j["version"] = info.version;
    j["generator"] = info.generator;
    j["nodes"] = info.nodes;
    j["triangles"] = info.drawnTriangles;
    json meshes = json::array();
    for (size_t i = 0; i < info.meshes.size(); ++i) {
        const GltfInfo::Mesh& m = info.meshes[i];
        json o = {{"index", i}, {"name", m.name}, {"primitives", m.primitives}, {"triangles", m.triangles},
                  {"vertices", m.vertices}, {"instances", m.instances}, {"skinned", m.skinned}, {"morph_targets", m.morphTargets}};
        if (m.gpuInstances) o["gpu_instances"] = m.gpuInstances;  // of "instances", drawn by EXT_mesh_gpu_instancing
        if (m.points) o["points"] = m.points;
        if (m.lineSegments) o["line_segments"] = m.lineSegments;
        o["bounds"] = m.hasBounds ? json{{"min", vec3f(m.min)}, {"max", vec3f(m.max)}} : json(nullptr);
        meshes.push_back(o);
    }
    j["meshes"] = meshes;
    json mats = json::array();
    for (size_t i = 0; i < info.materials.size(); ++i) {
        const GltfInfo::Material& m = info.materials[i];
        mats.push_back({{"index", i}, {"name", m.name}, {"alpha_mode", m.alphaMode}, {"double_sided", m.doubleSided},
                        {"extensions", m.extensions}});
    }
    j["materials"] = mats;
    json texs = json::array();
    for (size_t i = 0; i < info.textures.size(); ++i) {
        const GltfInfo::Texture& t = info.textures[i];
        texs.push_back({{"index", i}, {"name", t.name}, {"image", t.image}, {"source", t.source},
                        {"format", t.format.empty() ? json(nullptr) : json(t.format)},
                        {"width", t.width}, {"height", t.height}});
    }
    j["textures"] = texs;
    json anims = json::array();
    for (size_t i = 0; i < info.animations.size(); ++i) {
        const GltfInfo::Animation& a = info.animations[i];
        anims.push_back({{"index", i}, {"name", a.name}, {"duration_s", tidy(a.duration)}, {"channels", a.channels},
                         {"samplers", a.samplers}, {"paths", a.paths}});
    }
    j["animations"] = anims;
    json skins = json::array();
    for (size_t i = 0; i < info.skins.size(); ++i)
        skins.push_back({{"index", i}, {"name", info.skins[i].name}, {"joints", info.skins[i].joints},
                         {"inverse_bind_matrices", info.skins[i].inverseBindMatrices}});
    j["skins"] = skins;
    json cams = json::array();
    for (size_t i = 0; i < info.cameras.size(); ++i) {
        const GltfInfo::Camera& c = info.cameras[i];
        json o = {{"index", i}, {"name", c.name}, {"type", c.type}};
        if (c.type == "perspective") {
            o["yfov_deg"] = tidy(c.yfovDeg);
            o["aspect"] = c.aspect > 0.0 ? json(tidy(c.aspect)) : json(nullptr);
        } else {
            o["xmag"] = tidy(c.xmag);
            o["ymag"] = tidy(c.ymag);
        }
        o["znear"] = tidy(c.znear);
        o["zfar"] = c.zfar > 0.0 ? json(tidy(c.zfar)) : json(nullptr);
        o["rendered"] = c.type == "perspective" || c.type == "orthographic";  // still/render --camera N
        cams.push_back(o);
    }
    j["cameras"] = cams;
    j["camera_views"] = views;
    json scenes = json::array();
    for (size_t i = 0; i < info.scenes.size(); ++i)
        scenes.push_back({{"index", i}, {"name", info.scenes[i].name}, {"root_nodes", info.scenes[i].roots},
                          {"default", int(i) == info.defaultScene}, {"drawn", int(i) == info.drawnScene}});
    j["scenes"] = scenes;
    json lights = json::array();
    for (size_t i = 0; i < info.lights.size(); ++i) {
        const GltfInfo::Light& l = info.lights[i];
        lights.push_back({{"index", i}, {"name", l.name}, {"type", l.type}, {"intensity", tidy(l.intensity)}, {"unit", l.unit},
                          {"color", vec3f(l.color)}, {"range", l.range > 0.0 ? json(tidy(l.range)) : json(nullptr)}});
    }
    j["lights"] = lights;
    json ext = json::array();
    for (const GltfInfo::Extension& e : info.extensions)
        ext.push_back({{"name", e.name}, {"required", e.required}, {"supported", e.supported}});
    j["extensions"] = ext;
    j["variants"] = info.variants;
    j["turntable"] = turntable;
    return j;
}

std::string quoted(const std::string& name) { return name.empty() ? std::string("(no name)") : "\"" + name + "\""; }

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    // No "-0": a value that rounds to zero in the shown digits prints as 0, whatever its sign.
    if (buf[0] == '-' && std::strtod(buf, nullptr) == 0.0) return buf + 1;
    return buf;
}
std::string point(const json& v) {
    // Appended piece by piece: "(" + std::string&& trips GCC 12's false -Wrestrict (PR 105651)
    // at -O3 without link-time optimisation, which -Werror makes a failed build.
    std::string s = "(";
    s += fmt("%.4g", v[0].get<double>());
    s += ", ";
    s += fmt("%.4g", v[1].get<double>());
    s += ", ";
    s += fmt("%.4g", v[2].get<double>());
    s += ")";
    return s;
}
std::string joined(const json& arr, const char* sep = ", ") {
    std::string s;
    for (const auto& e : arr) {
        if (!s.empty()) s += sep;
        s += e.get<std::string>();
    }
    return s;
}

/// The same content as the JSON, a line per item.
std::string infoText(const json& j) {
    std::string s = j["file"].get<std::string>() + ": " +
                    (j.contains("format") ? j["format"].get<std::string>() + " read as glTF " : std::string("glTF ")) +
                    j["version"].get<std::string>();
    if (!j["generator"].get<std::string>().empty()) s += " from " + quoted(j["generator"]);
    s += ", " + std::to_string(j["nodes"].get<int>()) + " nodes, " + std::to_string(j["triangles"].get<uint64_t>()) + " triangles drawn\n";
    auto section = [&](const char* name, const json& arr) {
        s += std::string(name) + " (" + std::to_string(arr.size()) + ")" + (arr.empty() ? "\n" : ":\n");
    };
    section("meshes", j["meshes"]);
    for (const json& m : j["meshes"]) {
        s += "  " + std::to_string(m["index"].get<int>()) + " " + quoted(m["name"]) + ": " + std::to_string(m["triangles"].get<uint64_t>()) +
             " triangles, " + std::to_string(m["vertices"].get<uint64_t>()) + " vertices, " + std::to_string(m["primitives"].get<int>()) +
             " primitives, drawn " + std::to_string(m["instances"].get<uint64_t>()) + "x";
        if (m.contains("gpu_instances"))
            s += " (" + std::to_string(m["gpu_instances"].get<uint64_t>()) + " EXT_mesh_gpu_instancing instances)";
        if (m.contains("points")) s += ", " + std::to_string(m["points"].get<uint64_t>()) + " points";
        if (m.contains("line_segments")) s += ", " + std::to_string(m["line_segments"].get<uint64_t>()) + " line segments";
        if (m["skinned"].get<bool>()) s += ", skinned";
        if (m["morph_targets"].get<int>()) s += ", " + std::to_string(m["morph_targets"].get<int>()) + " morph targets";
        s += m["bounds"].is_null() ? "; no bounds" : "; bounds " + point(m["bounds"]["min"]) + " to " + point(m["bounds"]["max"]);
        s += "\n";
    }
    section("materials", j["materials"]);
    for (const json& m : j["materials"]) {
        s += "  " + std::to_string(m["index"].get<int>()) + " " + quoted(m["name"]) + ": " + m["alpha_mode"].get<std::string>() +
             (m["double_sided"].get<bool>() ? ", double-sided" : "");
        if (!m["extensions"].empty()) s += ", " + joined(m["extensions"]);
        s += "\n";
    }
    section("textures", j["textures"]);
    for (const json& t : j["textures"]) {
        s += "  " + std::to_string(t["index"].get<int>()) + " " + quoted(t["name"]) + ": ";
        s += t["format"].is_null() ? std::string("unknown format") : t["format"].get<std::string>();
        if (t["width"].get<int>() > 0) s += " " + std::to_string(t["width"].get<int>()) + "x" + std::to_string(t["height"].get<int>());
        s += ", image " + std::to_string(t["image"].get<int>()) + " (" + t["source"].get<std::string>() + ")\n";
    }
    section("animations", j["animations"]);
    for (const json& a : j["animations"])
        s += "  " + std::to_string(a["index"].get<int>()) + " " + quoted(a["name"]) + ": " + fmt("%.4g", a["duration_s"].get<double>()) +
             " s, " + std::to_string(a["channels"].get<int>()) + " channels (" + joined(a["paths"]) + ")\n";
    section("skins", j["skins"]);
    for (const json& k : j["skins"])
        s += "  " + std::to_string(k["index"].get<int>()) + " " + quoted(k["name"]) + ": " + std::to_string(k["joints"].get<int>()) + " joints\n";
    section("cameras", j["cameras"]);
    for (const json& c : j["cameras"]) {
        s += "  " + std::to_string(c["index"].get<int>()) + " " + quoted(c["name"]) + ": " + c["type"].get<std::string>();
        if (c.contains("yfov_deg")) s += ", vertical field of view " + fmt("%.4g", c["yfov_deg"].get<double>()) + " deg";
        if (c.contains("ymag")) s += ", a view " + fmt("%.4g", 2.0 * c["ymag"].get<double>()) + " units high";
        s += c["rendered"].get<bool>() ? "\n" : " (not rendered: rayfarm renders perspective and orthographic cameras)\n";
    }
    if (!j["camera_views"].empty()) s += "  through --camera N (in node order):\n";
    for (const json& v : j["camera_views"]) {
        s += "    --camera " + std::to_string(v["option"].get<int>()) + ": node " + std::to_string(v["node"].get<int>()) + " " +
             quoted(v["node_name"]) + ", camera " + std::to_string(v["camera"].get<int>());
        if (!v["usable"].get<bool>()) s += ", unusable";
        auto names = [&](const json& list) {
            std::string out;
            for (const json& a : list) {
                if (!out.empty()) out += ", ";
                out += std::to_string(a["index"].get<int>()) + " " + quoted(a["name"]) + " (" + fmt("%.4g", a["duration_s"].get<double>()) + " s)";
            }
            return out;
        };
        s += v["animated"].get<bool>() ? ", animated by " + names(v["animations"]) : std::string(", still");
        if (!v["lens_animations"].empty()) s += ", its lens keyed by " + names(v["lens_animations"]);
        s += "\n";
    }
    section("scenes", j["scenes"]);
    for (const json& sc : j["scenes"])
        s += "  " + std::to_string(sc["index"].get<int>()) + " " + quoted(sc["name"]) + ": " + std::to_string(sc["root_nodes"].get<int>()) +
             " root nodes" + (sc["default"].get<bool>() ? ", the file's default" : "") + (sc["drawn"].get<bool>() ? ", drawn" : "") + "\n";
    section("lights", j["lights"]);
    for (const json& l : j["lights"])
        s += "  " + std::to_string(l["index"].get<int>()) + " " + quoted(l["name"]) + ": " + l["type"].get<std::string>() + ", " +
             fmt("%.6g", l["intensity"].get<double>()) + " " + l["unit"].get<std::string>() + ", colour " + point(l["color"]) + "\n";
    section("extensions", j["extensions"]);
    for (const json& e : j["extensions"])
        s += "  " + e["name"].get<std::string>() + (e["required"].get<bool>() ? " (required)" : "") +
             (e["supported"].get<bool>() ? ": supported\n" : ": not supported, ignored\n");
    if (!j["variants"].empty()) {
        section("variants", j["variants"]);
        for (size_t i = 0; i < j["variants"].size(); ++i) s += "  " + std::to_string(i) + " " + quoted(j["variants"][i]) + "\n";
    }
    const json& t = j["turntable"];
    const json& c = t["camera"];
    const bool through = !t["through"].is_string();
    s += std::string(through ? "film through --camera " + std::to_string(t["through"].get<int>()) + ": " : "default turntable: ") +
         std::to_string(t["frames"].get<int>()) + " frames at " + fmt("%.4g", t["fps"].get<double>()) + " fps (" +
         fmt("%.4g", t["seconds"].get<double>()) + " s), " + std::to_string(t["width"].get<int>()) + "x" +
         std::to_string(t["height"].get<int>()) + ", " + std::to_string(t["spp"].get<int>()) + " spp\n";
    if (!through)
        s += "  camera " + fmt("%.4g", c["distance"].get<double>()) + " units from the target " + point(c["target"]) + " at " +
             fmt("%.3g", c["elevation_deg"].get<double>()) + " deg elevation, field of view " + fmt("%.3g", c["fov_deg"].get<double>()) +
             " deg, one orbit\n";
    else
        s += "  the camera's node moves with its animation, frame by frame\n";
    for (const json& a : t["animations"]) {
        s += "  plays animation " + std::to_string(a["index"].get<int>()) + " " + quoted(a["name"]) + " (" + fmt("%.4g", a["period_s"].get<double>()) + " s) ";
        if (a["ends_whole"].get<bool>()) s += std::to_string(a["whole_plays"].get<long long>()) + (a["whole_plays"].get<long long>() == 1 ? " whole play\n" : " whole plays\n");
        else s += fmt("%.4g", a["plays"].get<double>()) + " times (" + std::to_string(a["whole_plays"].get<long long>()) + " whole, looped)\n";
    }
    s += "  lit by " + t["lights"].get<std::string>() + "\n";
    return s;
}

}  // namespace

int runInfo(const std::vector<std::string>& args) {
    ArgParser p("info");
    for (const char* o : {"--size", "--fps", "--animation", "--asset-root", "--camera", "--scene"}) p.option(o);
    p.flag("--json");
    p.flag("--help");
    p.flag("-h");
    p.parse(args);
    if (p.has("--help") || p.has("-h")) {
        std::fputs(kInfoHelp, stdout);
        return 0;
    }
    if (p.positional().size() != 1) throw UsageError("info: expected one MODEL (see rayfarm info --help)");
    const std::string path = p.positional()[0];
    if (!isModelPath(path)) throw InputError(path, "info describes a model: glTF (.gltf or .glb) or .obj, .stl, .ply, .fbx, .dae and .3mf");
    const double fps = p.doubleValue("--fps", 0.0);
    if (p.has("--fps") && !(fps > 0.0 && fps <= 1000.0)) throw UsageError("--fps: expected a number above 0, up to 1000");
    SceneOptions opts = sceneOptions(p);
    // The whole load first: a file the renderer refuses is refused here with the same line. No
    // ray is traced, so no acceleration structure is built unless an animation poses the model
    // for frame 0's camera (posing refits the trees).
    opts.buildAccel = false;
    DiskFileSource fs;
    GltfInfo info;
    LoadedScene loaded = loadScene(path, fs, opts, &info);
    Scene& scene = loaded.scene;
    const anim::Timeline tl = anim::Timeline::fromScene(loaded, fps);
    if (tl.posesModels()) scene.build();
    const json j = infoJson(path, info, turntableJson(scene, tl, info.lights.size()), cameraViewsJson(scene));
    const std::string out = p.has("--json") ? j.dump(2) + "\n" : infoText(j);
    std::fwrite(out.data(), 1, out.size(), stdout);
    return std::fflush(stdout) == 0 ? 0 : 1;
}

}  // namespace rf::cli
