#include "farm/view/camera_keys.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "engine/util/model_path.h"
#include "engine/util/file_source.h"

namespace rf::view {

using json = nlohmann::json;

namespace {

json vec(const DVec3& v) { return json::array({v.x, v.y, v.z}); }
json vec(const Vec3& v) { return json::array({double(v.x), double(v.y), double(v.z)}); }

json track(const std::vector<CameraKey>& keys, const char* interpolation, json (*value)(const CameraKey&)) {
    json ks = json::array();
    for (const CameraKey& k : keys) ks.push_back({{"time", k.time}, {"value", value(k)}});
    return {{"interpolation", interpolation}, {"keys", ks}};
}

std::string absoluteFrom(const std::string& sceneFile, const std::string& rel) {
    if (std::filesystem::path(rel).is_absolute()) return rel;
    const auto base = std::filesystem::absolute(std::filesystem::path(sceneFile)).parent_path();
    return (base / rel).lexically_normal().string();
}

bool isModel(const std::string& path) { return isModelPath(path); }

const char* toneMapName(ToneMap t) {
    return t == ToneMap::Reinhard ? "reinhard" : t == ToneMap::PbrNeutral ? "pbr-neutral" : "clamp";
}

json lightJson(const Light& l, const DVec3& origin) {
    json j{{"name", l.name}, {"color", vec(l.color)}, {"intensity", double(l.intensity)}, {"shadows", l.castShadows}};
    j["type"] = l.type == LightType::Directional ? "directional" : l.type == LightType::Spot ? "spot" : "point";
    if (l.type != LightType::Directional) j["position"] = vec(DVec3(l.position) + origin);
    if (l.type != LightType::Point) j["direction"] = vec(l.direction);
    j["attenuation"] = vec(l.attenuation);
    return j;
}

/// A bare model as a scene file: what loadGltfScene made of it, written out.
json modelScene(const Scene& scene) {
    const DVec3 o = scene.renderOrigin;
    json doc;
    doc["camera"] = {{"eye", vec(DVec3(scene.camera.eye) + o)}, {"target", vec(DVec3(scene.camera.target) + o)},
                     {"up", vec(scene.camera.up)}, {"fov", double(scene.camera.fovDeg)},
                     {"fov_axis", scene.camera.fovHorizontal ? "horizontal" : "vertical"}};
    doc["ambient"] = vec(scene.ambientLight);
    // The default rig is not part of the model: write it, so the scene keeps its light. Lights
    // the model brings come back with the model.
    json lights = json::array();
    for (const Light& l : scene.lights)
        if (l.name.rfind("default ", 0) == 0) lights.push_back(lightJson(l, o));
    if (!lights.empty()) doc["lights"] = lights;
    doc["objects"] = json::array({{{"type", "model"}, {"path", absoluteFrom(scene.sourcePath, scene.sourcePath)}}});
    return doc;
}

}  // namespace

int CameraKeys::add(const CameraKey& k) {
    auto it = std::lower_bound(keys_.begin(), keys_.end(), k.time, [](const CameraKey& a, double t) { return a.time < t; });
    if (it != keys_.end() && std::abs(it->time - k.time) < 1e-9) {
        *it = k;
    } else {
        it = keys_.insert(it, k);
    }
    return static_cast<int>(it - keys_.begin());
}

void CameraKeys::remove(int index) {
    if (index >= 0 && size_t(index) < keys_.size()) keys_.erase(keys_.begin() + index);
}

CameraKey keyFromCamera(const Camera& c, const DVec3& renderOrigin, double t) {
    // A float plus a multiple of 64 is exact in double, so the loader's subtraction of the
    // origin gives the camera back bit for bit.
    return {t, DVec3(c.eye) + renderOrigin, DVec3(c.target) + renderOrigin, double(c.fovDeg)};
}

Film filmOf(const anim::Timeline& tl) {
    if (tl.frameCount() > 1) return {tl.frameCount(), tl.fps()};
    return {121, 30.0};
}

std::string sectionsText(const TimelineSource& source) { return source.sections ? source.sections->dump() : std::string(); }

TimelineSource withSections(const TimelineSource& base, const std::string& text) {
    TimelineSource out = base;
    // Keys made in the window replace the file's camera (--camera) the scene was opened with.
    if (text != sectionsText(base)) out.camera.reset();
    out.sections = text.empty() ? nullptr : std::make_shared<const json>(json::parse(text));
    return out;
}

json keyedTimeline(const CameraKeys& keys, const TimelineSource& source, const Film& film) {
    json base = source.sections ? *source.sections : json::object();
    json tl;
    if (base.contains("timeline")) {
        tl = base["timeline"];
    } else {
        tl = json::object();
        if (base.contains("turntable") && base["turntable"].contains("animation"))
            tl["animation"] = base["turntable"]["animation"];
    }
    tl["fps"] = film.fps;
    tl["frames"] = film.frames;
    tl.erase("duration");
    tl.erase("loop");
    json cam;
    cam["position"] = track(keys.keys(), "catmull-rom", [](const CameraKey& k) { return vec(k.eye); });
    cam["target"] = track(keys.keys(), "catmull-rom", [](const CameraKey& k) { return vec(k.target); });
    cam["fov"] = track(keys.keys(), "linear", [](const CameraKey& k) { return json(k.fovDeg); });
    tl["camera"] = cam;
    return tl;
}

json sceneDocument(const Scene& scene, const RenderSettings& s, const json& timeline) {
    json doc;
    if (isModel(scene.sourcePath)) {
        doc = modelScene(scene);
    } else {
        DiskFileSource fs;
        doc = json::parse(fs.read(scene.sourcePath, 1ull << 30));
        // The saved file may live elsewhere: models named relative to the source move with it.
        if (doc.contains("objects"))
            for (json& o : doc["objects"])
                if (o.value("type", "") == "model" && o.contains("path"))
                    o["path"] = absoluteFrom(scene.sourcePath, o["path"].get<std::string>());
    }
    doc.erase("turntable");
    // The background as shown (--background may have replaced the file's).
    doc["background"] = scene.transparentBackground ? json("transparent") : vec(scene.background);
    doc["timeline"] = timeline;
    json& r = doc["render"];
    r["width"] = s.width;
    r["height"] = s.height;
    r["spp"] = s.spp;
    r["max_depth"] = s.maxDepth;
    r["min_weight"] = double(s.minWeight);
    if (s.indirectSamples > 0) r["indirect"] = s.indirectSamples;
    if (s.bounce != kDefaultBounce) r["bounce"] = s.bounce;
    r["tonemap"] = toneMapName(s.toneMap);
    doc["exposure"] = s.autoExposure ? json("auto") : json(double(s.exposure));
    // The environment as lit (--environment may have replaced the file's, or the bare model's
    // built-in studio stands in for a rig): without it a saved glTF scene would go dark.
    if (scene.environment) {
        const EnvironmentSpec& e = scene.environmentSource;
        json env{{"rotation", double(e.rotationDeg)}, {"intensity", double(e.intensity)}};
        if (!e.file.empty()) env["file"] = std::filesystem::absolute(e.file).lexically_normal().string();
        doc["environment"] = env;
    } else {
        doc.erase("environment");
    }
    return doc;
}

void writeSceneFile(const std::string& path, const json& doc) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream f(tmp);
        f << doc.dump(2) << "\n";
        if (!f) throw std::runtime_error(path + ": cannot write the scene file");
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw std::runtime_error(path + ": cannot write the scene file (" + ec.message() + ")");
}

}  // namespace rf::view
