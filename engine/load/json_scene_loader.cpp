#include "engine/load/json_scene_loader.h"

#include <algorithm>
#include <filesystem>
#include <new>
#include <optional>
#include <set>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "engine/scene/env_lighting.h"
#include "engine/util/errors.h"
#include "engine/util/json_reader.h"
#include "engine/util/model_path.h"
#include "engine/util/sample_count.h"
#include "engine/integrators/shadow_catcher.h"
#include "engine/load/assimp/assimp_import.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/json_guard.h"
#include "engine/util/load_control.h"
#include "engine/geometry/render_origin.h"

namespace rf {

namespace {

using nlohmann::json;


using Reader = JsonReader;

void readCamera(const Reader& rd, const json& j, Camera& cam, DVec3& eye, DVec3& target) {
    const std::string w = "camera";
    rd.allowKeys(j, w, {"eye", "position", "target", "up", "type", "fov", "fov_axis", "xmag", "ymag", "handedness"});
    eye = j.contains("eye") ? rd.dvec3(j["eye"], "camera.eye") : rd.dvec3(j, "position", w, DVec3(0, 0, 5));
    target = rd.dvec3(j, "target", w, DVec3(0.0));
    if (eye == target) rd.fail("camera.target", "eye and target coincide, so the view direction is undefined");
    const DVec3 up = rd.dvec3(j, "up", w, DVec3(0, 1, 0));
    if (glm::length(up) == 0.0) rd.fail("camera.up", "expected a non-zero vector");
    cam.up = Vec3(up);
    const std::string type = rd.string(j, "type", w, "perspective");
    if (type != "perspective" && type != "orthographic") rd.fail("camera.type", "expected \"perspective\" or \"orthographic\"");
    if (type == "orthographic") {
        // glTF's names: the view's half height (ymag) or half width (xmag) in scene units, the
        // other from the image's aspect. One of them, as a perspective camera has one fov.
        if (j.contains("fov") || j.contains("fov_axis"))
            rd.fail(j.contains("fov") ? "camera.fov" : "camera.fov_axis", "an orthographic camera has no field of view; give xmag or ymag");
        if (j.contains("xmag") == j.contains("ymag"))
            rd.fail("camera", "an orthographic camera needs one of xmag (half width) or ymag (half height), in scene units");
        const char* key = j.contains("xmag") ? "xmag" : "ymag";
        const double mag = rd.number(j, key, w, 1.0);
        if (!(mag > 0.0 && mag < 1e30)) rd.fail(std::string("camera.") + key, "expected a positive half extent in scene units");
        cam.orthographic = true;
        cam.orthoHalf = static_cast<float>(mag);
        cam.fovHorizontal = j.contains("xmag");
    } else {
        for (const char* key : {"xmag", "ymag"})
            if (j.contains(key)) rd.fail(std::string("camera.") + key, "only an orthographic camera (\"type\": \"orthographic\") has one");
        const double fov = rd.number(j, "fov", w, 45.0);
        if (!(fov > 0.0 && fov < 180.0)) rd.fail("camera.fov", "expected degrees in (0, 180)");
        cam.fovDeg = static_cast<float>(fov);
        const std::string axis = rd.string(j, "fov_axis", w, "vertical");
        if (axis != "vertical" && axis != "horizontal") rd.fail("camera.fov_axis", "expected \"vertical\" or \"horizontal\"");
        cam.fovHorizontal = axis == "horizontal";
    }
    const std::string hand = rd.string(j, "handedness", w, "right");
    if (hand != "right" && hand != "left") rd.fail("camera.handedness", "expected \"right\" or \"left\"");
    cam.leftHanded = hand == "left";
}

void readRender(const Reader& rd, const json& j, RenderSettings& s) {
    const std::string w = "render";
    rd.allowKeys(j, w, {"width", "height", "spp", "max_depth", "min_weight", "tonemap", "shading", "tile_size", "indirect", "bounce"});
    s.width = rd.integer(j, "width", w, s.width, 1, 16384);
    s.height = rd.integer(j, "height", w, s.height, 1, 16384);
    s.spp = rd.integer(j, "spp", w, s.spp, 1, 4096);
    if (const std::string why = sppProblem(s.spp); !why.empty()) rd.fail("render.spp", why);
    s.maxDepth = rd.integer(j, "max_depth", w, s.maxDepth, 1, 64);
    s.minWeight = static_cast<float>(rd.nonNegative(j, "min_weight", w, s.minWeight));
    const std::string tm = rd.string(j, "tonemap", w, "clamp");
    if (tm == "clamp") s.toneMap = ToneMap::Clamp;
    else if (tm == "reinhard") s.toneMap = ToneMap::Reinhard;
    else if (tm == "pbr-neutral") s.toneMap = ToneMap::PbrNeutral;
    else rd.fail("render.tonemap", "expected \"clamp\", \"reinhard\" or \"pbr-neutral\"");
    const std::string sh = rd.string(j, "shading", w, "phong");
    if (sh == "phong") s.shading = ShadingModel::Phong;
    else if (sh == "blinn-phong") s.shading = ShadingModel::BlinnPhong;
    else rd.fail("render.shading", "expected \"phong\" or \"blinn-phong\"");
    s.tileSize = rd.integer(j, "tile_size", w, s.tileSize, 1, 4096);
    s.indirectSamples = rd.integer(j, "indirect", w, s.indirectSamples, 0, kMaxIndirectSamples);
    s.bounce = rd.integer(j, "bounce", w, s.bounce, 0, kMaxBounce);
    if (j.contains("bounce")) s.bounceMoving = true;  // asked for: moving geometry too
}

/// "exposure": an EV (radiance × 2^EV before tone mapping) or "auto" (metered once per film).
void readExposure(const Reader& rd, const json& j, RenderSettings& s) {
    if (j.is_string() && j.get<std::string>() == "auto") {
        s.autoExposure = true;
        return;
    }
    const double ev = rd.number(j, "exposure");
    if (std::abs(ev) > 64.0) rd.fail("exposure", "expected \"auto\" or an EV from -64 to 64");
    s.exposure = float(ev);
}

Material readMaterial(const Reader& rd, const json& j, const std::string& w, const std::string& name) {
    rd.allowKeys(j, w, {"color", "checker", "ambient", "diffuse", "specular", "shininess", "reflection", "transmission",
                        "ior", "emission", "double_sided"});
    Material m;
    m.name = name;
    m.color = rd.color(j, "color", w, m.color);
    if (j.contains("checker")) {
        const json& c = j["checker"];
        const std::string cw = w + ".checker";
        rd.allowKeys(c, cw, {"color2", "scale"});
        m.color2 = rd.color(c, "color2", cw, m.color2);
        m.checkerScale = static_cast<float>(rd.positive(c, "scale", cw, 1.0));
    }
    m.ambient = static_cast<float>(rd.nonNegative(j, "ambient", w, m.ambient));
    m.diffuse = static_cast<float>(rd.nonNegative(j, "diffuse", w, m.diffuse));
    m.specular = static_cast<float>(rd.nonNegative(j, "specular", w, m.specular));
    m.shininess = static_cast<float>(rd.nonNegative(j, "shininess", w, m.shininess));
    m.reflection = static_cast<float>(rd.nonNegative(j, "reflection", w, m.reflection));
    m.transmission = static_cast<float>(rd.nonNegative(j, "transmission", w, m.transmission));
    m.ior = static_cast<float>(rd.positive(j, "ior", w, m.ior));
    m.emission = rd.color(j, "emission", w, m.emission);
    m.doubleSided = rd.boolean(j, "double_sided", w, true);
    return m;
}

Light readLight(const Reader& rd, const json& j, const std::string& w, const DVec3& origin) {
    rd.allowKeys(j, w, {"type", "name", "position", "direction", "color", "intensity", "attenuation", "inner_angle",
                        "outer_angle", "range", "shadows"});
    Light l;
    l.name = rd.string(j, "name", w, "");
    const std::string type = rd.string(j, "type", w, "point");
    if (type == "point") l.type = LightType::Point;
    else if (type == "directional") l.type = LightType::Directional;
    else if (type == "spot") l.type = LightType::Spot;
    else rd.fail(w + ".type", "expected \"point\", \"directional\" or \"spot\"");
    if (l.type != LightType::Directional) {
        if (!j.contains("position")) rd.fail(w, "a " + type + " light needs a position");
        l.position = Vec3(rd.dvec3(j["position"], w + ".position") - origin);
    }
    if (l.type != LightType::Point) {
        if (!j.contains("direction")) rd.fail(w, "a " + type + " light needs a direction");
        l.direction = Vec3(rd.unit(rd.dvec3(j["direction"], w + ".direction"), w + ".direction"));
    }
    l.color = rd.color(j, "color", w, l.color);
    l.intensity = static_cast<float>(rd.nonNegative(j, "intensity", w, 1.0));
    const DVec3 att = rd.dvec3(j, "attenuation", w, DVec3(1, 0, 0));
    if (att.x < 0 || att.y < 0 || att.z < 0) rd.fail(w + ".attenuation", "coefficients must be ≥ 0");
    if (att.x == 0 && att.y == 0 && att.z == 0)
        rd.fail(w + ".attenuation", "a = b = c = 0 makes 1/(a + b·d + c·d²) infinite");
    l.attenuation = Vec3(att);
    if (l.type == LightType::Spot) {
        const double inner = rd.nonNegative(j, "inner_angle", w, 0.0);
        const double outer = rd.positive(j, "outer_angle", w, 45.0);
        if (outer > 90.0) rd.fail(w + ".outer_angle", "expected at most 90 degrees");
        if (inner > outer) rd.fail(w + ".inner_angle", "must not exceed outer_angle");
        l.innerCone = static_cast<float>(glm::radians(inner));
        l.outerCone = static_cast<float>(glm::radians(outer));
    }
    l.range = static_cast<float>(rd.nonNegative(j, "range", w, 0.0));
    l.castShadows = rd.boolean(j, "shadows", w, true);
    return l;
}

DMat4 readTransform(const Reader& rd, const json& j, const std::string& w) {
    if (j.is_array()) {
        if (j.size() != 16) rd.fail(w, "expected 16 numbers (a column-major matrix) or an object");
        DMat4 m;
        for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = rd.number(j[i], Reader::index(w, i));
        return m;
    }
    rd.allowKeys(j, w, {"translate", "rotate", "scale"});
    DMat4 m(1.0);
    m = glm::translate(m, rd.dvec3(j, "translate", w, DVec3(0.0)));
    const DVec3 r = rd.dvec3(j, "rotate", w, DVec3(0.0));  // degrees about x, then y, then z
    m = glm::rotate(m, glm::radians(r.z), DVec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(r.y), DVec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(r.x), DVec3(1, 0, 0));
    DVec3 s(1.0);
    if (j.contains("scale")) s = j["scale"].is_number() ? DVec3(rd.number(j["scale"], w + ".scale")) : rd.dvec3(j["scale"], w + ".scale");
    if (s.x == 0 || s.y == 0 || s.z == 0) rd.fail(w + ".scale", "a zero scale flattens the object");
    return glm::scale(m, s);
}

std::vector<Vec3> readPoints(const Reader& rd, const json& j, const std::string& w, const DVec3& origin, bool isDirection) {
    if (!j.is_array()) rd.fail(w, "expected an array of [x, y, z]");
    std::vector<Vec3> out;
    out.reserve(j.size());
    for (size_t i = 0; i < j.size(); ++i) {
        if (i % 65536 == 0) pollLoadCancel();
        const DVec3 p = rd.dvec3(j[i], Reader::index(w, i));
        out.push_back(Vec3(isDirection ? p : p - origin));
    }
    return out;
}

class JsonSceneLoader {
public:
    JsonSceneLoader(const std::string& path, FileSource& fs, const SceneOptions& options)
        : path_(path), fs_(fs), rd_(path), options_(options) {}

    LoadedScene load() {
        LoadedScene loaded;
        Scene& s = loaded.scene;
        std::optional<EnvironmentSpec> environment;
        bool fileGround = false;
        {
            json root;
            try {
                root = parseUserJson(path_, fs_.read(path_, 1ull << 30));
                readDocument(root, s, fileGround);
                if (root.contains("environment")) environment = readEnvironment(root["environment"]);
            } catch (const std::bad_alloc&) {
                abandonJson(root);  // freeing it would need memory there is none of
                throw;
            }
        }  // the document goes before the environment and the BVH: for a million spheres it is most of the peak
        attachEnvironment(s, environment, options_, fs_);
        s.build();
        if (fileGround) placeGround(s, Ground::Shadow);  // the command line's --ground, if any, comes after
        loaded.timeline.sections = std::move(timeline_);
        loaded.timeline.camera = camera_;
        loaded.timeline.cameraSource = cameraSource_;
        return loaded;
    }

private:
    /// Everything the document says but the environment, into s.
    void readDocument(const json& root, Scene& s, bool& fileGround) {
        LoadStep reading("reading the scene's objects");
        rd_.allowKeys(root, "", {"camera", "background", "ambient", "render", "materials", "lights", "objects", "timeline",
                                 "turntable", "exposure", "environment", "ground", "asset_root", "comment"});
        // "asset_root": the folder the models' URIs may reach, relative to this file (--asset-root wins).
        assets_ = options_.assets;
        if (root.contains("asset_root") && !options_.rootFromCommandLine) {
            const std::string r = rd_.string(root, "asset_root", "", "");
            if (r.empty()) rd_.fail("asset_root", "expected a folder name");
            const std::filesystem::path base = std::filesystem::path(path_).parent_path();
            assets_.root = (std::filesystem::path(r).is_absolute() ? std::filesystem::path(r) : base / r).lexically_normal().string();
            if (assets_.root.empty()) assets_.root = ".";
        }
        s.sourcePath = path_;
        DVec3 eye(0, 0, 5), target(0.0);
        if (root.contains("camera")) readCamera(rd_, root["camera"], s.camera, eye, target);
        const DVec3 view = glm::normalize(target - eye), up = glm::normalize(DVec3(s.camera.up));
        if (glm::length(glm::cross(view, up)) < 1e-6)
            s.notes.push_back(path_ + ": camera.up is parallel to the view direction; the camera uses the world axis least aligned with the view as up");
        s.renderOrigin = chooseRenderOrigin(target);
        s.camera.eye = Vec3(eye - s.renderOrigin);
        s.camera.target = Vec3(target - s.renderOrigin);
        if (root.contains("background") && root["background"].is_string()) {
            // "transparent": misses give alpha 0; reflections still see the default background.
            if (root["background"].get<std::string>() != "transparent")
                rd_.fail("background", "expected [r, g, b] or \"transparent\"");
            s.transparentBackground = true;
        } else {
            s.background = rd_.color(root, "background", "", s.background);
        }
        s.ambientLight = rd_.color(root, "ambient", "", s.ambientLight);
        fileGround = root.contains("ground") && readGround(root["ground"]) == Ground::Shadow;
        if (root.contains("render")) readRender(rd_, root["render"], s.settings);
        applyRenderSize(options_, s.settings);
        if (root.contains("exposure")) readExposure(rd_, root["exposure"], s.settings);
        readMaterials(root, s);
        if (root.contains("lights")) {
            const json& ls = root["lights"];
            if (!ls.is_array()) rd_.fail("lights", "expected an array");
            for (size_t i = 0; i < ls.size(); ++i, pollLoadCancel()) s.lights.push_back(readLight(rd_, ls[i], Reader::index("lights", i), s.renderOrigin));
        }
        if (root.contains("objects")) {
            const json& os = root["objects"];
            if (!os.is_array()) rd_.fail("objects", "expected an array");
            for (size_t i = 0; i < os.size(); ++i) {
                pollLoadCancel();
                readObject(os[i], Reader::index("objects", i), s);
            }
        }
        if (!assets_.variant.empty() && modelVariants_ == 0)
            throw InputError(path_, assets_.variantSource + ": no model in the scene has material variants (KHR_materials_variants)");
        json anim = json::object();
        if (root.contains("timeline") && root["timeline"].is_string()) {
            // A timeline in its own file: read through the FileSource (so farm workers get it in
            // the bundle) and inline it; anim/ names "timeline_file" in its errors.
            const std::string rel = root["timeline"].get<std::string>();
            const std::filesystem::path base = std::filesystem::path(path_).parent_path();
            const std::string full = (std::filesystem::path(rel).is_absolute() ? std::filesystem::path(rel) : base / rel).lexically_normal().string();
            anim["timeline"] = parseUserJson(full, fs_.read(full, 1ull << 28));
            anim["timeline_file"] = full;
        } else if (root.contains("timeline")) {
            anim["timeline"] = root["timeline"];
        }
        if (root.contains("turntable")) anim["turntable"] = root["turntable"];
        if (!anim.empty()) timeline_ = std::make_shared<const json>(std::move(anim));
    }

private:
    void readMaterials(const json& root, Scene& s) {
        Material def;
        def.name = "default";
        s.materials.push_back(def);
        materialIds_["default"] = 0;
        if (!root.contains("materials")) return;
        const json& ms = root["materials"];
        if (!ms.is_object()) rd_.fail("materials", "expected an object of name: material");
        for (auto it = ms.begin(); it != ms.end(); ++it) {
            pollLoadCancel();
            const std::string w = "materials." + it.key();
            Material m = readMaterial(rd_, it.value(), w, it.key());
            if (materialIds_.count(it.key())) {
                s.materials[materialIds_[it.key()]] = m;
            } else {
                materialIds_[it.key()] = static_cast<int>(s.materials.size());
                s.materials.push_back(m);
            }
        }
    }

    int material(const json& j, const std::string& w) {
        const std::string name = rd_.string(j, "material", w, "default");
        auto it = materialIds_.find(name);
        if (it == materialIds_.end()) rd_.fail(w + ".material", "no material named \"" + name + "\"");
        return it->second;
    }

    void readObject(const json& j, const std::string& w, Scene& s) {
        if (!j.is_object()) rd_.fail(w, "expected an object");
        const std::string type = rd_.string(j, "type", w, "");
        const DVec3& o = s.renderOrigin;
        if (type == "sphere") {
            rd_.allowKeys(j, w, {"type", "center", "radius", "material"});
            Sphere sp;
            sp.center = Vec3(rd_.dvec3(j, "center", w, DVec3(0.0)) - o);
            sp.radius = static_cast<float>(rd_.positive(j, "radius", w, 1.0));
            sp.material = material(j, w);
            s.geometry.spheres.push_back(sp);
        } else if (type == "plane") {
            rd_.allowKeys(j, w, {"type", "normal", "point", "material"});
            Plane pl;
            const DVec3 n = rd_.unit(rd_.dvec3(j, "normal", w, DVec3(0, 1, 0)), w + ".normal");
            const DVec3 p = rd_.dvec3(j, "point", w, DVec3(0.0)) - o;
            pl.n = Vec3(n);
            pl.d = static_cast<float>(-glm::dot(n, p));
            pl.material = material(j, w);
            s.geometry.planes.push_back(pl);
        } else if (type == "triangle" || type == "mesh") {
            readMesh(j, w, s, type == "triangle");
        } else if (type == "model") {
            rd_.allowKeys(j, w, {"type", "path", "transform", "material", "variant", "scene", "camera"});
            const std::string rel = rd_.string(j, "path", w, "");
            if (rel.empty()) rd_.fail(w + ".path", "expected the model's file name");
            const std::filesystem::path base = std::filesystem::path(path_).parent_path();
            const std::string full = (std::filesystem::path(rel).is_absolute() ? std::filesystem::path(rel) : base / rel).lexically_normal().string();
            const DMat4 m = j.contains("transform") ? readTransform(rd_, j["transform"], w + ".transform") : DMat4(1.0);
            // "material": the scene's (Phong) material for every primitive in place of the
            // file's own, a clay render (gltf_loader.h).
            // "variant": the model's KHR_materials_variants variant; --variant overrides it for
            // every model that has variants (and a model without variants then keeps its own).
            AssetOptions a = assets_;
            if (!a.variant.empty()) {
                a.variantRequired = false;
            } else if (j.contains("variant")) {
                a.variant = rd_.string(j, "variant", w, "");
                if (a.variant.empty()) rd_.fail(w + ".variant", "expected a variant's name");
                a.variantSource = w + ".variant";
            }
            // "scene": which of the file's scenes (--scene overrides it for every model).
            if (a.scene < 0 && j.contains("scene")) {
                if (!j["scene"].is_number_integer() || j["scene"].get<long long>() < 0) rd_.fail(w + ".scene", "expected a scene index from 0");
                a.scene = int(std::min<long long>(j["scene"].get<long long>(), 1 << 20));
                a.sceneSource = w + ".scene";
            }
            const size_t camerasBefore = s.gltfCameras.size();
            // OBJ, STL, PLY, FBX, COLLADA and 3MF through assimp, as the glTF model each becomes.
            if (isAssimpPath(full)) loadAssimpModel(s, full, m, fs_, j.contains("material") ? material(j, w) : -1, a);
            else modelVariants_ += loadGltfModel(s, full, m, fs_, j.contains("material") ? material(j, w) : -1, a);
            // "camera": the film looks through this model's camera N (--camera overrides it).
            if (j.contains("camera")) {
                if (!j["camera"].is_number_integer() || j["camera"].get<long long>() < 0) rd_.fail(w + ".camera", "expected a camera index from 0");
                const long long c = j["camera"].get<long long>();
                const size_t has = s.gltfCameras.size() - camerasBefore;
                if (c >= (long long)has)
                    rd_.fail(w + ".camera", "no camera " + std::to_string(c) + " (" + rel + " has " + std::to_string(has) + (has == 1 ? " camera)" : " cameras)"));
                if (camera_) rd_.fail(w + ".camera", "another model already gives the camera");
                camera_ = int(camerasBefore + size_t(c));
                cameraSource_ = w + ".camera";
            }
        } else {
            rd_.fail(w + ".type", "expected \"sphere\", \"plane\", \"triangle\", \"mesh\" or \"model\"");
        }
    }

    void readMesh(const json& j, const std::string& w, Scene& s, bool single) {
        TriangleMesh m;
        const DVec3& o = s.renderOrigin;
        if (single) {
            rd_.allowKeys(j, w, {"type", "vertices", "normals", "material"});
            if (!j.contains("vertices")) rd_.fail(w, "a triangle needs \"vertices\"");
            m.positions = readPoints(rd_, j["vertices"], w + ".vertices", o, false);
            if (m.positions.size() != 3) rd_.fail(w + ".vertices", "expected 3 points");
            m.indices = {0, 1, 2};
        } else {
            rd_.allowKeys(j, w, {"type", "positions", "indices", "normals", "uvs", "material"});
            if (!j.contains("positions")) rd_.fail(w, "a mesh needs \"positions\"");
            m.positions = readPoints(rd_, j["positions"], w + ".positions", o, false);
            if (j.contains("indices")) {
                const json& ix = j["indices"];
                if (!ix.is_array() || ix.size() % 3 != 0) rd_.fail(w + ".indices", "expected a multiple of 3 integers");
                for (size_t i = 0; i < ix.size(); ++i) {
                    if (i % 65536 == 0) pollLoadCancel();
                    if (!ix[i].is_number_unsigned() || ix[i].get<uint64_t>() >= m.positions.size())
                        rd_.fail(Reader::index(w + ".indices", i), "expected an index below " + std::to_string(m.positions.size()));
                    m.indices.push_back(ix[i].get<uint32_t>());
                }
            } else {
                if (m.positions.size() % 3 != 0) rd_.fail(w + ".positions", "without indices, expected a multiple of 3 points");
                for (uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
            }
            if (j.contains("uvs")) {
                const json& u = j["uvs"];
                if (!u.is_array() || u.size() != m.positions.size()) rd_.fail(w + ".uvs", "expected one [u, v] per position");
                for (size_t i = 0; i < u.size(); ++i) {
                    if (!u[i].is_array() || u[i].size() != 2) rd_.fail(Reader::index(w + ".uvs", i), "expected 2 numbers");
                    m.uvs.emplace_back(rd_.number(u[i][0], w + ".uvs"), rd_.number(u[i][1], w + ".uvs"));
                }
            }
        }
        if (j.contains("normals")) {
            m.normals = readPoints(rd_, j["normals"], w + ".normals", o, true);
            if (m.normals.size() != m.positions.size()) rd_.fail(w + ".normals", "expected one normal per position");
        }
        m.material = material(j, w);
        s.geometry.meshes.push_back(std::move(m));
    }

    /// "ground": "shadow" (an invisible shadow catcher under the model) or "none".
    Ground readGround(const json& j) const {
        const std::string g = j.is_string() ? j.get<std::string>() : "";
        if (g == "shadow") return Ground::Shadow;
        if (g != "none") rd_.fail("ground", "expected \"shadow\" or \"none\"");
        return Ground::None;
    }

    /// "environment": "FILE" or {"file": FILE (none: the built-in studio), "rotation": degrees
    /// about +Y, "intensity": k}. FILE is relative to the scene file.
    EnvironmentSpec readEnvironment(const json& j) const {
        EnvironmentSpec e;
        const std::filesystem::path base = std::filesystem::path(path_).parent_path();
        auto resolve = [&](const std::string& f) {
            return (std::filesystem::path(f).is_absolute() ? std::filesystem::path(f) : base / f).lexically_normal().string();
        };
        if (j.is_string()) {
            e.file = resolve(j.get<std::string>());
            return e;
        }
        if (!j.is_object()) rd_.fail("environment", "expected a file name or an object");
        rd_.allowKeys(j, "environment", {"file", "rotation", "intensity"});
        const std::string f = rd_.string(j, "file", "environment", "");
        if (!f.empty()) e.file = resolve(f);
        e.rotationDeg = float(rd_.number(j, "rotation", "environment", 0.0));
        e.intensity = float(rd_.nonNegative(j, "intensity", "environment", 1.0));
        return e;
    }

    std::string path_;
    FileSource& fs_;
    Reader rd_;
    SceneOptions options_;
    AssetOptions assets_;  ///< options_.assets with the file's "asset_root"
    size_t modelVariants_ = 0;  ///< material variants of all the scene's models
    std::map<std::string, int> materialIds_;
    std::shared_ptr<const json> timeline_;  ///< the animation sections, for the LoadedScene
    std::optional<int> camera_;             ///< a model's "camera", as an index into Scene::gltfCameras
    std::string cameraSource_ = "--camera";
};

}  // namespace

LoadedScene loadJsonScene(const std::string& path, FileSource& fs, const SceneOptions& options) {
    return JsonSceneLoader(path, fs, options).load();
}

}  // namespace rf
