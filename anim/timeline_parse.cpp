// The timeline format (TimelineSource::sections = {"timeline": {...}} or {"turntable": {...}}):
//
//   "timeline": {
//     "fps": 30, "duration": 4, "start": 0,   // seconds; duration defaults to the last key
//     "frames": 121,                          // optional; default round(duration·fps) + 1,
//     "loop": false,                          //   or round(duration·fps) when looping
//     "camera": { "position": TRACK, "target": TRACK | "orientation": TRACK, "up": TRACK,
//                 "fov": TRACK, "orbit": {"center", "radius", "height", "period", "phase"} },
//     "lights": [ { "light": 0 | "name", "position", "direction", "color", "intensity",
//                   "inner_angle", "outer_angle": TRACK } ],
//     "animation": true | false | {"model", "name" | "index", "mode": "loop" | "clamp", "speed", "offset"}
//                  | [ ...one per model... ]
//   }
//   TRACK = { "interpolation": "linear", "keys": [ {"time", "value", "interpolation", "in", "out"} ] }
//           or just the keys array.
//
// Positions are world space (render space = world − renderOrigin). Angles in degrees. The full
// description, with the turntable section, is anim/timeline_format.md.
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "engine/util/errors.h"
#include "engine/util/json_reader.h"
#include "anim/frame_time.h"
#include "engine/util/json_guard.h"
#include "engine/util/model_path.h"
#include "anim/timeline_spec.h"

namespace rf::anim {

namespace {

using nlohmann::json;

/// The timeline section's reader: the scene reader's typed reads, plus tracks and keys.
class Parser : public JsonReader {
public:
    Parser(std::string file, std::string prefix, const Scene& scene, const std::optional<std::string>& animation)
        : JsonReader(std::move(file), std::move(prefix)), scene_(scene), animation_(animation) {}

    DVec3 vec3(const json& j, const std::string& w) const { return dvec3(j, w); }
    /// obj["fps"] (def when absent), within the rates a film can have.
    double frameRate(const json& obj, const std::string& w, double def) const {
        const double fps = positive(obj, "fps", w, def);
        if (!fpsInRange(fps)) fail(join(w, "fps"), kFpsRangeText);
        return fps;
    }
    /// A key's value (or tangent) with dim components; a colour may be one grey number.
    std::vector<double> values(const json& j, const std::string& w, int dim, bool greyOk) const {
        if (j.is_number() && (dim == 1 || greyOk)) return std::vector<double>(dim, number(j, w));
        if (!j.is_array() || static_cast<int>(j.size()) != dim) fail(w, "expected " + std::to_string(dim) + (dim == 1 ? " number" : " numbers"));
        std::vector<double> v(dim);
        for (int c = 0; c < dim; ++c) v[c] = number(j[c], w);
        return v;
    }

    /// kind: what the track animates, for value checks.
    enum class Kind { Point, Direction, Up, Color, NonNegative, Fov, Angle, Rotation };

    KeyTrack track(const json& j, const std::string& w, Kind kind) const {
        const int dim = kind == Kind::Rotation ? 4 : (kind == Kind::NonNegative || kind == Kind::Fov || kind == Kind::Angle ? 1 : 3);
        Interp def = Interp::Linear;
        const json* keys = &j;
        std::string kw = w;
        if (j.is_object()) {
            allowKeys(j, w, {"interpolation", "keys"});
            if (j.contains("interpolation")) def = interp(j["interpolation"], join(w, "interpolation"), kind);
            if (!j.contains("keys")) fail(w, "a track needs \"keys\"");
            keys = &j["keys"];
            kw = join(w, "keys");
        }
        if (!keys->is_array() || keys->empty()) fail(kw, "expected an array of at least one key");
        KeyTrack t(dim, kind == Kind::Rotation);
        for (size_t k = 0; k < keys->size(); ++k) {
            const json& key = (*keys)[k];
            const std::string w2 = index(kw, k);
            allowKeys(key, w2, {"time", "value", "interpolation", "in", "out"});
            if (!key.contains("time")) fail(w2, "a key needs a \"time\" in seconds");
            if (!key.contains("value")) fail(w2, "a key needs a \"value\"");
            const double time = number(key["time"], join(w2, "time"));
            std::vector<double> v = values(key["value"], join(w2, "value"), dim, kind == Kind::Color);
            checkValue(v, join(w2, "value"), kind);
            if (kind == Kind::Point)  // file positions are world space; the scene is rebased
                for (int c = 0; c < 3; ++c) v[c] -= scene_.renderOrigin[c];
            const Interp how = key.contains("interpolation") ? interp(key["interpolation"], join(w2, "interpolation"), kind) : def;
            std::vector<double> in, out;
            if (key.contains("in")) in = values(key["in"], join(w2, "in"), dim, false);
            if (key.contains("out")) out = values(key["out"], join(w2, "out"), dim, false);
            try {
                t.addKey(time, v.data(), how, in.empty() ? nullptr : in.data(), out.empty() ? nullptr : out.data());
            } catch (const KeyError& e) {
                fail(join(index(kw, static_cast<size_t>(e.key())), e.field()), e.what());
            }
        }
        return t;
    }

    Interp interp(const json& j, const std::string& w, Kind kind) const {
        if (!j.is_string()) fail(w, "expected an interpolation name");
        Interp i;
        const std::string name = j.get<std::string>();
        if (!parseInterp(name, i))
            fail(w, "unknown interpolation \"" + name + "\" (expected step, linear, slerp, hermite, catmull-rom, ease, ease-in or ease-out)");
        if (kind == Kind::Rotation && i == Interp::CatmullRom) fail(w, "catmull-rom is not defined for orientations; use slerp");
        if (kind != Kind::Rotation && name == "slerp") fail(w, "slerp is for orientation tracks; use linear");
        return i;
    }

    void checkValue(const std::vector<double>& v, const std::string& w, Kind kind) const {
        switch (kind) {
            case Kind::Direction:
            case Kind::Up:
                if (v[0] == 0 && v[1] == 0 && v[2] == 0) fail(w, "expected a non-zero vector");
                break;
            case Kind::Color:
                for (double x : v)
                    if (x < 0) fail(w, "colour components must be ≥ 0");
                break;
            case Kind::NonNegative:
                if (v[0] < 0) fail(w, "expected a number ≥ 0");
                break;
            case Kind::Fov:
                if (!(v[0] > 0 && v[0] < 180)) fail(w, "expected degrees in (0, 180)");
                break;
            case Kind::Angle:
                if (!(v[0] >= 0 && v[0] <= 90)) fail(w, "expected degrees from 0 to 90");
                break;
            default: break;
        }
    }

    std::optional<KeyTrack> optTrack(const json& o, const char* k, const std::string& w, Kind kind) const {
        if (!o.contains(k)) return std::nullopt;
        return track(o[k], join(w, k), kind);
    }

    CameraTracks camera(const json& j, const std::string& w) const {
        allowKeys(j, w, {"position", "target", "orientation", "up", "fov", "orbit"});
        CameraTracks c;
        if (j.contains("orbit") && j.contains("position")) fail(join(w, "orbit"), "give either an orbit or a position track");
        if (j.contains("orientation") && (j.contains("target") || j.contains("up")))
            fail(join(w, "orientation"), "an orientation replaces target and up; give one or the other");
        c.position = optTrack(j, "position", w, Kind::Point);
        c.target = optTrack(j, "target", w, Kind::Point);
        c.orientation = optTrack(j, "orientation", w, Kind::Rotation);
        c.up = optTrack(j, "up", w, Kind::Up);
        c.fov = optTrack(j, "fov", w, Kind::Fov);
        if (j.contains("orbit")) {
            const json& o = j["orbit"];
            const std::string ow = join(w, "orbit");
            allowKeys(o, ow, {"center", "radius", "height", "period", "phase"});
            Orbit orb;
            if (o.contains("center")) orb.center = vec3(o["center"], join(ow, "center"));
            orb.radius = positive(o, "radius", ow, 1.0);
            orb.height = number(o, "height", ow, 0.0);
            orb.period = positive(o, "period", ow, 1.0);
            orb.phase = number(o, "phase", ow, 0.0);
            c.orbit = orb;
        }
        return c;
    }

    int lightIndex(const json& j, const std::string& w) const {
        const int n = static_cast<int>(scene_.lights.size());
        if (j.is_number_integer()) {
            const long long i = j.get<long long>();
            if (i < 0 || i >= n) fail(w, "no light " + std::to_string(i) + " (the scene has " + std::to_string(n) + ")");
            return static_cast<int>(i);
        }
        if (j.is_string()) {
            const std::string name = j.get<std::string>();
            for (int i = 0; i < n; ++i)
                if (scene_.lights[i].name == name) return i;
            fail(w, "no light named \"" + name + "\"");
        }
        fail(w, "expected a light index or name");
    }

    LightTracks light(const json& j, const std::string& w) const {
        allowKeys(j, w, {"light", "position", "direction", "color", "intensity", "inner_angle", "outer_angle"});
        if (!j.contains("light")) fail(w, "say which light: \"light\": index or name");
        LightTracks l;
        l.light = lightIndex(j["light"], join(w, "light"));
        l.position = optTrack(j, "position", w, Kind::Point);
        l.direction = optTrack(j, "direction", w, Kind::Direction);
        l.color = optTrack(j, "color", w, Kind::Color);
        l.intensity = optTrack(j, "intensity", w, Kind::NonNegative);
        l.innerDeg = optTrack(j, "inner_angle", w, Kind::Angle);
        l.outerDeg = optTrack(j, "outer_angle", w, Kind::Angle);
        return l;
    }

    /// "animation": absent → every animated model plays its default animations (defaultAnimations), looped.
    std::vector<GltfAnimationPlayer> animations(const json& o, const std::string& w) const {
        // The command line's --animation wins over the file's choice.
        if (!o.contains("animation") || animation_) return defaultPlayers(scene_, animation_);
        const json& a = o["animation"];
        const std::string aw = join(w, "animation");
        std::vector<GltfAnimationPlayer> players;
        if (a.is_boolean()) return a.get<bool>() ? defaultPlayers(scene_, animation_) : players;
        if (a.is_string() && a.get<std::string>() == "none") return players;
        if (a.is_string()) return chosen(a.get<std::string>(), aw);
        if (a.is_number_integer()) return chosen(std::to_string(a.get<long long>()), aw);
        if (a.is_object()) {
            players.push_back(player(a, aw));
        } else if (a.is_array()) {
            for (size_t i = 0; i < a.size(); ++i) players.push_back(player(a[i], index(aw, i)));
        } else {
            fail(aw, "expected true, false, \"none\", a name, an index, an object or an array of objects");
        }
        return players;
    }

    /// "animation": NAME or INDEX: every animated model plays that one; "all": all of its own.
    std::vector<GltfAnimationPlayer> chosen(const std::string& choice, const std::string& w) const {
        std::vector<GltfAnimationPlayer> players;
        for (size_t m = 0; m < scene_.geometry.models.size(); ++m) {
            const SceneGraph& g = scene_.geometry.models[m];
            if (g.animations.empty()) continue;
            if (choice == kAllAnimations && findAnimation(g, choice) < 0) {
                std::vector<int> all(g.animations.size());
                for (size_t a = 0; a < all.size(); ++a) all[a] = int(a);
                players.emplace_back(g, static_cast<int>(m), all, true);
                continue;
            }
            const int a = chooseAnimation(g, choice);
            if (a < 0) fail(w, missingAnimation(g, choice));
            players.emplace_back(g, static_cast<int>(m), a, true);
        }
        if (players.empty()) fail(w, "the scene has no model animations to choose from");
        return players;
    }

    GltfAnimationPlayer player(const json& j, const std::string& w) const {
        allowKeys(j, w, {"model", "name", "index", "mode", "speed", "offset"});
        const int nModels = static_cast<int>(scene_.geometry.models.size());
        int model = 0;
        if (j.contains("model")) {
            if (!j["model"].is_number_integer()) fail(join(w, "model"), "expected a model index");
            model = j["model"].get<int>();
        }
        if (model < 0 || model >= nModels) fail(join(w, "model"), "no model " + std::to_string(model) + " (the scene has " + std::to_string(nModels) + ")");
        const SceneGraph& g = scene_.geometry.models[model];
        if (g.animations.empty()) fail(w, "model " + std::to_string(model) + " (" + g.source + ") has no animations");
        if (j.contains("name") && j.contains("index")) fail(w, "give either a name or an index");
        int anim = 0;
        if (j.contains("name")) {
            if (!j["name"].is_string()) fail(join(w, "name"), "expected a string");
            anim = findAnimation(g, j["name"].get<std::string>());
            if (anim < 0) fail(join(w, "name"), "the model has no animation named \"" + j["name"].get<std::string>() + "\"");
        } else if (j.contains("index")) {
            if (!j["index"].is_number_integer()) fail(join(w, "index"), "expected an integer");
            anim = j["index"].get<int>();
            if (anim < 0 || anim >= static_cast<int>(g.animations.size()))
                fail(join(w, "index"), "no animation " + std::to_string(anim) + " (the model has " + std::to_string(g.animations.size()) + ")");
        }
        bool loop = true;
        if (j.contains("mode")) {
            const std::string m = j["mode"].is_string() ? j["mode"].get<std::string>() : "";
            if (m == "loop") loop = true;
            else if (m == "clamp") loop = false;
            else fail(join(w, "mode"), "expected \"loop\" or \"clamp\"");
        }
        return GltfAnimationPlayer(g, model, anim, loop, number(j, "speed", w, 1.0), number(j, "offset", w, 0.0));
    }

    /// fps > 0 replaces the section's own rate (render --fps).
    TurntableSettings turntable(const json& j, const std::string& w, double fps) const {
        allowKeys(j, w, {"seconds", "fps", "elevation", "distance", "lights", "center", "start_yaw", "fov", "animation", "comment"});
        // A bare model's rig is placed for its camera, so there lights follow it by default.
        TurntableSettings s = isModelPath(scene_.sourcePath) ? defaultModelTurntable() : TurntableSettings{};
        s.seconds = positive(j, "seconds", w, s.seconds);
        s.fps = fps > 0.0 ? fps : frameRate(j, w, s.fps);
        s.elevationDeg = number(j, "elevation", w, s.elevationDeg);
        if (s.elevationDeg < -90 || s.elevationDeg > 90) fail(join(w, "elevation"), "expected degrees from −90 to 90");
        if (j.contains("distance") && !(j["distance"].is_string() && j["distance"].get<std::string>() == "auto"))
            s.distance = positive(j, "distance", w, 1.0);
        if (j.contains("lights")) {
            const std::string m = j["lights"].is_string() ? j["lights"].get<std::string>() : "";
            if (m == "fixed") s.lightsFollow = false;
            else if (m == "follow-camera") s.lightsFollow = true;
            else fail(join(w, "lights"), "expected \"fixed\" or \"follow-camera\"");
        }
        if (j.contains("center")) s.center = vec3(j["center"], join(w, "center"));
        s.startYawDeg = number(j, "start_yaw", w, 0.0);
        if (j.contains("fov")) {
            const double f = number(j["fov"], join(w, "fov"));
            if (!(f > 0 && f < 180)) fail(join(w, "fov"), "expected degrees in (0, 180)");
            s.fovDeg = f;
        }
        if (anim::frameCount(s.seconds, s.fps) < 1 || s.seconds * s.fps > 1e9) fail(w, "seconds × fps is out of range");
        return s;
    }

private:
    const Scene& scene_;
    const std::optional<std::string>& animation_;  ///< --animation, over the file's choice
};

double maxEnd(const std::optional<KeyTrack>& t, double d) { return t ? std::max(d, t->endTime()) : d; }

}  // namespace

TurntableSettings defaultModelTurntable() {
    TurntableSettings s;
    s.seconds = 4.0;
    s.fps = 30.0;
    s.elevationDeg = 20.0;
    s.lightsFollow = true;
    s.fitSilhouette = true;
    return s;
}

std::vector<GltfAnimationPlayer> defaultPlayers(const Scene& scene, const std::optional<std::string>& animation) {
    if (animation) return chosenPlayers(scene, *animation, "", "--animation");
    std::vector<GltfAnimationPlayer> players;
    for (size_t m = 0; m < scene.geometry.models.size(); ++m)
        if (!scene.geometry.models[m].animations.empty())
            players.emplace_back(scene.geometry.models[m], static_cast<int>(m), defaultAnimations(scene.geometry.models[m]), true);
    return players;
}

std::vector<GltfAnimationPlayer> chosenPlayers(const Scene& scene, const std::string& choice, const std::string& file,
                                               const std::string& where) {
    std::vector<GltfAnimationPlayer> players;
    for (size_t m = 0; m < scene.geometry.models.size(); ++m) {
        const SceneGraph& g = scene.geometry.models[m];
        if (g.animations.empty()) continue;
        if (choice == kAllAnimations && findAnimation(g, choice) < 0) {
            std::vector<int> all(g.animations.size());
            for (size_t a = 0; a < all.size(); ++a) all[a] = int(a);
            players.emplace_back(g, static_cast<int>(m), all, true);
            continue;
        }
        const int a = chooseAnimation(g, choice);
        if (a < 0) throw InputError(file.empty() ? g.source : file, where + ": " + missingAnimation(g, choice));
        players.emplace_back(g, static_cast<int>(m), a, true);
    }
    if (players.empty()) {
        if (scene.geometry.models.size() == 1)
            throw InputError(file.empty() ? scene.geometry.models[0].source : file,
                             where + ": " + missingAnimation(scene.geometry.models[0], choice));
        throw InputError(file.empty() ? scene.sourcePath : file, where + ": the scene has no model animations to choose from");
    }
    return players;
}

double longestPeriod(const std::vector<GltfAnimationPlayer>& players) {
    double p = 0.0;
    for (const GltfAnimationPlayer& pl : players) p = std::max(p, pl.period());
    return p;
}

Aabb filmBounds(const Scene& scene, const std::vector<GltfAnimationPlayer>& players, int frames, double fps) {
    Aabb b = scene.geometry.bounds();
    if (players.empty()) return b;
    std::vector<std::vector<MeshExtent>> extents;
    for (const GltfAnimationPlayer& p : players) extents.push_back(meshExtents(scene, p.model()));
    const int samples = std::min(frames, 256);
    for (int i = 0; i < samples; ++i) {
        const long long f = samples == frames ? i : static_cast<long long>(double(i) * (frames - 1) / (samples - 1));
        for (size_t k = 0; k < players.size(); ++k) players[k].growPosedBounds(scene, anim::frameTime(0.0, fps, f), extents[k], b);
    }
    return b;
}

Turntable framedOnFilm(const TurntableSettings& s, const Scene& scene, const std::vector<GltfAnimationPlayer>& players) {
    const int n = anim::frameCount(s.seconds, s.fps);
    const Aabb bounds = filmBounds(scene, players, n, s.fps);
    if (players.empty() || n > kMaxFramedFrames) return Turntable::framed(s, scene, bounds, !players.empty());
    std::vector<std::vector<MeshExtent>> extents;
    for (const GltfAnimationPlayer& p : players) extents.push_back(meshExtents(scene, p.model()));
    const double fps = s.fps;
    const Turntable::PosedPoints posed = [&](int f, const std::function<void(const DVec3&)>& emit) {
        for (size_t k = 0; k < players.size(); ++k)
            players[k].visitPosed(scene, anim::frameTime(0.0, fps, f), extents[k], [&](const Vec3& p) { emit(DVec3(p)); });
    };
    return Turntable::framed(s, scene, bounds, true, &posed);
}

ParsedTimeline parseTimeline(const Scene& scene, const TimelineSource& source, double fps) {
    ParsedTimeline out;
    out.spec.restLights = scene.lights;
    if (!source.sections) return out;
    const json& root = *source.sections;
    if (!root.is_object()) throw InputError(scene.sourcePath, "timeline: expected an object");
    if (root.contains("timeline") && root.contains("turntable"))
        throw InputError(scene.sourcePath, "turntable: give either a timeline or a turntable, not both");

    if (root.contains("turntable")) {
        const Parser p(scene.sourcePath, "", scene, source.animation);
        TurntableSettings s = p.turntable(root["turntable"], "turntable", fps);
        out.spec.players = p.animations(root["turntable"], "turntable");
        if (!root["turntable"].contains("seconds")) s.seconds = filmSecondsForClip(longestPeriod(out.spec.players), s.seconds);
        out.spec.turntable = framedOnFilm(s, scene, out.spec.players);
        out.frames = out.spec.turntable->frameCount();
        out.fps = s.fps;
        return out;
    }
    if (!root.contains("timeline")) return out;
    // A timeline in its own file was inlined by the scene loader, which names the file.
    const bool external = root.contains("timeline_file") && root["timeline_file"].is_string();
    const std::string file = external ? root["timeline_file"].get<std::string>() : scene.sourcePath;
    const Parser p(file, external ? "" : "timeline.", scene, source.animation);
    const json& j = root["timeline"];
    p.allowKeys(j, "", {"fps", "duration", "frames", "start", "loop", "camera", "lights", "animation", "comment"});
    out.fps = fps > 0.0 ? fps : p.frameRate(j, "", 30.0);
    out.t0 = p.number(j, "start", "", 0.0);
    TimelineSpec& s = out.spec;
    if (j.contains("camera")) s.camera = p.camera(j["camera"], "camera");
    if (j.contains("lights")) {
        const json& ls = j["lights"];
        if (!ls.is_array()) p.fail("lights", "expected an array");
        for (size_t i = 0; i < ls.size(); ++i) s.lights.push_back(p.light(ls[i], Parser::index("lights", i)));
    }
    s.players = p.animations(j, "");

    double end = 0.0;
    const CameraTracks& c = s.camera;
    for (const auto* t : {&c.position, &c.target, &c.orientation, &c.up, &c.fov}) end = maxEnd(*t, end);
    for (const LightTracks& l : s.lights)
        for (const auto* t : {&l.position, &l.direction, &l.color, &l.intensity, &l.innerDeg, &l.outerDeg}) end = maxEnd(*t, end);
    if (c.orbit) end = std::max(end, c.orbit->period);
    for (const GltfAnimationPlayer& pl : s.players) end = std::max(end, pl.duration());
    const double duration = j.contains("duration") ? p.number(j["duration"], "duration") : std::max(0.0, end - out.t0);
    if (duration < 0.0) p.fail("duration", "expected a number ≥ 0");
    if (duration * out.fps > 1e9) p.fail("duration", "duration × fps exceeds 10⁹ frames");
    bool loop = false;
    if (j.contains("loop")) {
        if (!j["loop"].is_boolean()) p.fail("loop", "expected true or false");
        loop = j["loop"].get<bool>();
    }
    if (j.contains("frames")) {
        if (!j["frames"].is_number_integer() || j["frames"].get<long long>() < 1 || j["frames"].get<long long>() > 1000000000)
            p.fail("frames", "expected an integer from 1 to 10⁹");
        out.frames = j["frames"].get<int>();
    } else if (duration > 0.0) {
        // A film includes both ends (its last key is rendered); a loop leaves out the frame
        // that would repeat the first.
        out.frames = anim::frameCount(duration, out.fps) + (loop ? 0 : 1);
    }
    return out;
}

}  // namespace rf::anim
