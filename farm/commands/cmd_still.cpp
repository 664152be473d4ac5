// rayfarm still: one frame to a PNG, on all local cores.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "farm/cli/background_option.h"
#include "farm/cli/cli.h"
#include "farm/commands/commands.h"
#include "engine/util/errors.h"
#include "farm/cli/exposure_meter.h"
#include "engine/load/gltf/gltf_loader.h"
#include "engine/util/image.h"
#include "farm/process/interrupt.h"
#include "farm/process/load_watch.h"
#include "farm/output/output_check.h"
#include "farm/output/output_paths.h"
#include "engine/integrators/render.h"
#include "farm/output/run_stats.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::cli {

namespace {
const char* kStillHelp =
    "usage: rayfarm still SCENE|MODEL [options]\n"
    "\n"
    "Renders one frame of a scene file (.json) or model to a PNG: glTF (.gltf/.glb), or OBJ, STL,\n"
    "PLY, FBX, COLLADA (.dae) and 3MF read as the glTF model each becomes.\n"
    "\n"
    "  -o FILE           output PNG (default: the scene's name with .png, here)\n"
    "  --size WxH        image size (default: the scene's render.width/height)\n"
    "  --spp N           samples per pixel, a square: 1, 4, 9, 16, ... (stratified)\n"
    "  --depth N         maximum ray depth; the primary ray counts as 1\n"
    "  --min-weight W    do not trace secondary rays weighing less than W (0: never prune)\n"
    "  --indirect N      glTF materials: N traced samples per lobe of environment and bounce\n"
    "                    light (occlusion, one bounce) instead of the unshadowed split sum\n"
    "                    (0, the default: noise-free); converges to a path tracer as N grows\n"
    "  --bounce N        glTF materials with --indirect 0: the lights' diffuse bounce, cached on\n"
    "                    N thousand surface points (default 3; 0: no bounce light)\n"
    "  --tonemap T       clamp, reinhard or pbr-neutral (default: clamp for scene files,\n"
    "                    pbr-neutral for glTF models)\n"
    "  --exposure EV     scale radiance by 2^EV before tone mapping; 0 shows glTF's photometric\n"
    "                    units at 683 lm/W unchanged; auto (the glTF default) meters the film once\n"
    "  --threads N       worker threads (default: all cores)\n"
    "  --stats FILE      write run statistics as JSON\n"
    "  --frame N         render frame N of the scene's timeline (default 0)\n"
    "  --time T          render the timeline at T seconds (noise seed of the nearest frame)\n"
    "  --camera N        look through the model's glTF camera N (in node order, from 0), posed by\n"
    "                    its node's animation at the frame's time (the scene file's \"camera\")\n"
    "  --scene N         draw the glTF file's scene N (default: the file's \"scene\", else 0)\n"
    "  --background B    transparent (a PNG with alpha: coverage, anti-aliased edges included),\n"
    "                    #RRGGBB (sRGB) or R,G,B (linear): exactly that colour where no model\n"
    "                    is, not exposed or tone-mapped; default: the scene's\n"
    "  --environment F   light the scene with an equirectangular .hdr or .exr environment\n"
    "                    (Blender's orientation), also seen where rays miss everything\n"
    "  --environment-rotation DEG   turn it about +Y;  --environment-intensity K   scale it\n"
    "  --ground G        shadow: an invisible ground under the model that shows only the shadows\n"
    "                    and contact darkening on it (with a transparent background, as alpha);\n"
    "                    none: no ground (default: the scene file's \"ground\")\n"
    "  --animation A     play the model's animation named A (or numbered A, from 0), or all of\n"
    "                    them together (all), instead of the default: every animation that moves\n"
    "                    what no earlier one moves (the scene file's \"animation\"); unknown:\n"
    "                    refused, listing them\n"
    "  --asset-root DIR  folder a glTF model's relative URIs may reach beyond its own (default:\n"
    "                    the current directory when the model lies under it, else its folder)\n"
    "  --max-texture-size N   textures larger on a side are downsampled on load (default 8192)\n"
    "  --point-size PX   glTF points and lines drawn PX pixels wide at a 640x360 default framing\n"
    "                    (default 1.5; a share of the model's size, so it scales with the picture)\n"
    "  --variant NAME    show the model's KHR_materials_variants variant NAME (the scene file's\n"
    "                    model \"variant\"); unknown: refused, listing the file's variants\n";

/// Sets the scene to the still's moment and returns its frame index (the noise seed). The still
/// is one frame of the scene's film: frame 0 unless --frame or --time says otherwise.
int applyStillTime(const ArgParser& p, const anim::Timeline& timeline, Scene& scene) {
    if (p.has("--frame") && p.has("--time")) throw UsageError("still: give --frame or --time, not both");
    int frame = p.intValue("--frame", 0, 0, timeline.frameCount() - 1);
    if (p.has("--time")) {
        const double t = p.doubleValue("--time", 0.0);
        const double f = std::round((t - timeline.frameTime(0)) * timeline.fps());
        frame = f > 0.0 ? static_cast<int>(std::min(f, 2e9)) : 0;
        timeline.apply(scene, t);
    } else {
        timeline.applyFrame(scene, frame);
    }
    return frame;
}

struct StillTimes {
    double loadS, renderS, wallS;
};

void writeStillStats(const std::string& path, const Scene& scene, const RenderSettings& settings, int threads,
                     const RayStats& rays, const StillTimes& t) {
    RunStats s;
    s.frames = 1;
    s.width = settings.width;
    s.height = settings.height;
    s.mode = "still";
    s.threadsPerRank = threads;
    s.wallSeconds = t.wallS;
    s.renderSeconds = t.renderS;
    s.sustainedFps = 1.0 / std::max(t.renderS, 1e-9);
    s.rays = rays;
    s.perRank.push_back({0, t.renderS, 1, 0});
    s.extra["load_s"] = t.loadS;
    s.extra["triangles"] = static_cast<double>(scene.geometry.triangleCount());
    s.extra["exposure_ev"] = settings.exposure;  // as given, or as metered by --exposure auto
    s.extraText["bvh"] = scene.geometry.usesBvh() ? "yes" : "no (scene too small to profit)";
    writeStatsJson(path, s);
}

}  // namespace

int runStill(const std::vector<std::string>& args) {
    ArgParser p("still");
    for (const char* o : {"-o", "--size", "--spp", "--depth", "--min-weight", "--indirect", "--bounce", "--tonemap", "--threads", "--stats", "--frame", "--time", "--background", "--exposure"}) p.option(o);
    declareSceneOptions(p);
    p.flag("--help");
    p.flag("-h");
    p.parse(args);
    if (p.has("--help") || p.has("-h")) {
        std::fputs(kStillHelp, stdout);
        return 0;
    }
    if (p.positional().size() != 1) throw UsageError("still: expected one SCENE or MODEL (see rayfarm still --help)");
    const std::string scenePath = p.positional()[0];
    const std::string out = p.value("-o").value_or(std::filesystem::path(scenePath).stem().string() + ".png");
    const int threads = p.intValue("--threads", 0, 1, 4096);
    BackgroundChoice background;
    if (auto b = p.value("--background")) background = parseBackground(*b);
    // still writes PNG only: a name that says otherwise (x.mp4, x.jpg) would hold PNG bytes.
    if (const std::string ext = std::filesystem::path(out).extension().string(); !ext.empty() && ext != ".png" && ext != ".PNG")
        throw UsageError(out + ": still writes a PNG: expected a .png file name (a video: rayfarm render)");
    const std::vector<NamedOutput> outputs = {{"-o", out}, {"--stats", p.value("--stats").value_or("")}};
    std::vector<std::string> inputs = {scenePath};
    if (auto env = p.value("--environment")) inputs.push_back(*env);
    checkOutputPaths(outputs, inputs);
    checkWritableFile(out);
    if (auto st = p.value("--stats")) checkWritableFile(*st);
    // Past `ulimit -f`: EFBIG, reported, instead of SIGXFSZ's silent death. Ctrl-C while loading:
    // one line within a second (load_watch.h); while rendering it ends the process at once.
    farm::installInterruptHandlers();

    const auto t0 = std::chrono::steady_clock::now();
    DiskFileSource fs;
    LoadedScene loaded;
    Scene& scene = loaded.scene;
    {
        farm::LoadWatch watch(scenePath, true);
        try {
            loaded = loadScene(scenePath, fs, sceneOptions(p));
        } catch (const LoadCancelled& c) {
            return watch.interrupted(c);
        }
        watch.done();
    }
    farm::restoreDefaultSignals();
    {
        std::vector<std::string> read;  // the model's buffers and textures, the environment
        for (const auto& [path, bytes] : fs.bundle().files) read.push_back(path);
        checkOutputPaths(outputs, read);
    }
    // Built before posing: auto exposure meters the film's own frames. Before the notes: a
    // --camera or --animation the file lacks is refused in one line.
    const anim::Timeline timeline = anim::Timeline::fromScene(loaded);
    for (const std::string& note : scene.notes) printLine("note", note);
    applyBackground(background, scene);
    const int frame = applyStillTime(p, timeline, scene);
    // --camera: the timeline looks through the glTF camera, posed by its node's animation at
    // the frame's time (anim::Timeline, TimelineSource::camera).
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    settings.bounceMoving = true;  // a still poses its model once: the cache is built once either way
    // One bounce cache for the metering frames and the still.
    const auto bounceSlot = std::make_shared<SceneCacheSlot>();
    if (settings.autoExposure) {
        resolveAutoExposure(scene, timeline, settings, threads, {}, bounceSlot);
    }

    RayStats rays;
    const auto t1 = std::chrono::steady_clock::now();
    const Image img = renderFrame(scene, {scene.camera, settings, bounceSlot}, frame, threads, rays);
    const auto t2 = std::chrono::steady_clock::now();
    writeReplacing(out, [&](const std::string& to) {
        if (img.hasAlpha() && !img.hasBackdrop()) writePng(to, img.width(), img.height(), toRgba8(img, settings.toneMap, exposureScale(settings.exposure)), 4);
        else writePng(to, img.width(), img.height(), toRgb8(img, settings));
    });
    const auto t3 = std::chrono::steady_clock::now();

    const double renderS = std::chrono::duration<double>(t2 - t1).count();
    const double wallS = std::chrono::duration<double>(t3 - t0).count();
    std::fprintf(stderr, "rayfarm: wrote %s (%dx%d, %d spp, depth %d) in %.3f s render, %.2f Mrays/s\n", printable(out).c_str(),
                 settings.width, settings.height, settings.spp, settings.maxDepth, renderS,
                 rays.total() / std::max(renderS, 1e-9) * 1e-6);
    if (rays.nonFinite) std::fprintf(stderr, "rayfarm: note: %llu non-finite samples replaced by black\n", (unsigned long long)rays.nonFinite);
    if (auto st = p.value("--stats"))
        writeStillStats(*st, scene, settings, threads > 0 ? threads : hardwareThreads(), rays,
                        {std::chrono::duration<double>(t1 - t0).count(), renderS, wallS});
    return 0;
}

}  // namespace rf::cli
