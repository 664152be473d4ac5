#include "farm/commands/render_options.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include "farm/cli/background_option.h"
#include "anim/frame_time.h"
#include "farm/output/video_format.h"

namespace rf::cli {

const char* kRenderHelp =
    "usage: rayfarm render SCENE|MODEL -o out.mp4|.webm|.mov|.gif [options]\n"
    "       rayfarm render A.glb B.glb ... -o 'out/{name}.mp4' [options]   (one job, many films)\n"
    "       mpirun -np N rayfarm render SCENE|MODEL -o out.mp4 [options]\n"
    "\n"
    "Renders the scene's timeline (a bare model: the default turntable) to a video. A model is\n"
    "glTF (.gltf/.glb), or OBJ, STL, PLY, FBX, COLLADA (.dae) or 3MF read as the glTF it becomes.\n"
    "Without mpirun it runs as one process on all cores; under mpirun rank 0 hands out work.\n"
    "Several scenes make one job of several films, one after another on the same ranks: {name}\n"
    "(the scene file's name without its extension) in -o, --frames-dir, --stats, --contact-sheet\n"
    "and --poster names each film's file; a film that fails does not stop the others, and the\n"
    "job exits non-zero naming it; --resume applies film by film.\n"
    "\n"
    "  -o FILE           the video (required); its name picks the format: .mp4 H.264, .webm VP9\n"
    "                    (with alpha when transparent), .mov ProRes 4444 (with alpha), .gif\n"
    "                    (a palette made for the film, looping)\n"
    "  --mode M          pixel (tiles of every frame), frame (whole frames) or auto (default)\n"
    "  --frames A:B      frames A to B of the timeline, inclusive (default: all); A: or :B too\n"
    "  --fps N           frame rate of the timeline and the video (default: the scene's; a\n"
    "                    bare model's turntable: 30). A still scene: the video's rate only\n"
    "  --size WxH        image size (odd sizes: the video repeats the last row/column to even)\n"
    "  --spp N           samples per pixel, a square: 1, 4, 9, ...\n"
    "  --environment F, --environment-rotation DEG, --environment-intensity K   as for still\n"
    "  --ground shadow|none   a shadow-catcher ground under the model, as for still\n"
    "  --animation A     play the model's animation named A (or numbered A, from 0), or all;\n"
    "                    as for still\n"
    "  --camera N        the film looks through the model's glTF camera N, following its node's\n"
    "                    animation; the film lasts that animation (both ends) unless the scene\n"
    "                    file's timeline sets it\n"
    "  --scene N         draw the glTF file's scene N (default: the file's \"scene\", else 0)\n"
    "  --asset-root DIR, --max-texture-size N   glTF asset folder and texture size, as for still\n"
    "  --point-size PX   how wide glTF points and lines are drawn, as for still\n"
    "  --variant NAME    the model's material variant NAME (KHR_materials_variants), as for still\n"
    "  --depth N         maximum ray depth; --min-weight W, --tonemap clamp|reinhard|pbr-neutral,\n"
    "                    --exposure EV|auto as for still (auto: one EV metered for the whole film)\n"
    "  --indirect N      glTF materials: N traced samples of indirect light (as for still)\n"
    "  --bounce N        glTF materials: cached bounce light on N thousand points (as for still;\n"
    "                    default 3, but none for a film whose geometry moves unless given)\n"
    "  --frames-dir DIR  keep a PNG per frame here as frames complete (default: OUT.frames next\n"
    "                    to the output, e.g. out.mp4.frames/ for out.mp4)\n"
    "  --no-frames       keep no PNG frames (then nothing can be resumed)\n"
    "  --preview         open a window (rayfarm view --watch) on the frames as they complete;\n"
    "                    closing it does not stop the render\n"
    "  --resume          render only the frames missing from the frames directory, then encode\n"
    "                    the whole video again (the same settings are required)\n"
    "  --overwrite       render every frame again over an earlier run's frames directory\n"
    "                    (without it or --resume, a directory holding frames is refused)\n"
    "  --codec C         h264 (.mp4), vp9 (.webm), prores (.mov), gif (.gif): only the file's own\n"
    "  --crf N           quality, lower is better: H.264 0-51 (default 18), VP9 0-63 (32);\n"
    "                    ProRes and GIF have none\n"
    "  --preset P        H.264: x264 preset, ultrafast ... placebo (default ultrafast); VP9: the\n"
    "                    same names as cpu-used 8 ... 0; ProRes: profile 4444 (default), 4444xq,\n"
    "                    hq, standard, lt, proxy; GIF: dither sierra2_4a (default), bayer,\n"
    "                    floyd_steinberg, none\n"
    "  --background B    transparent (alpha: PNG frames RGBA, .webm/.mov/.gif carry it, .mp4 is\n"
    "                    laid over the scene's background colour), #RRGGBB or R,G,B (linear):\n"
    "                    exactly that colour where no model is, not exposed or tone-mapped\n"
    "  --frames-format F png (default) or exr: also a half-float OpenEXR per frame, linear and\n"
    "                    not tone-mapped, with alpha (premultiplied)\n"
    "  --contact-sheet F a PNG grid of evenly spaced frames labelled with frame and time; written\n"
    "                    when the film completes or is interrupted, from finished frames only\n"
    "  --poster F        one frame full size as PNG (--poster-frame N, default the first)\n"
    "  --lossless        RGB H.264 at qp 0: decodes to the PNG frames bit for bit (not every\n"
    "                    player plays it; for reference comparisons)\n"
    "  --chunk-frames N  frames a video chunk (default: about 2 s of film; at least 2): each\n"
    "                    chunk starts with a key frame and has an encoder of its own, so the\n"
    "                    rank that renders a chunk in frame mode encodes it; the file is the same\n"
    "                    at any rank count for the same N\n"
    "  --threads N       render threads per rank (default: the node's cores shared by its ranks)\n"
    "  --timeout S       seconds a worker may stay silent before it counts as lost (default 10):\n"
    "                    its work goes to the other ranks (mpirun --enable-recovery keeps the job\n"
    "                    alive when a rank dies; without it mpirun ends the job); the workers\n"
    "                    leave when rank 0 ends (seen on its machine), or is silent twice that\n"
    "                    long\n"
    "  --max-frame-failures K  stop when K ranks were lost while rendering the same frame (a\n"
    "                    frame that takes down every worker it reaches; default 3)\n"
    "  --stats FILE      write run statistics as JSON (sustained_fps, per-rank busy time, ...)\n"
    "\n"
    "Ctrl-C stops cleanly: the MP4 holds the frames done so far and the command to resume is\n"
    "printed. A worker that dies or stays silent is named and its work goes to the others; the\n"
    "run stops, with the command to resume, when no rendering rank is left.\n"
    "Threads: Open MPI binds each rank to one core when it starts two or fewer ranks; each rank\n"
    "renders with the cores it is bound to (mpirun --bind-to none: the node's cores shared).\n";

void declareRenderOptions(ArgParser& p) {
    for (const char* o : {"-o", "--mode", "--frames", "--fps", "--size", "--spp", "--depth", "--min-weight", "--indirect", "--bounce", "--tonemap",
                          "--exposure", "--frames-dir", "--crf", "--preset", "--stats", "--threads", "--timeout", "--max-frame-failures", "--codec",
                          "--background", "--frames-format", "--contact-sheet", "--poster", "--poster-frame", "--chunk-frames"})
        p.option(o);
    for (const char* f : {"--resume", "--overwrite", "--lossless", "--no-frames", "--preview", "--help", "-h"}) p.flag(f);
    declareSceneOptions(p);
}

const std::vector<OptionRole>& renderOptionRoles() {
    static const std::vector<OptionRole> roles = {
        // The picture: each reaches the identity, resolved (the scene's own value when not given).
        {"--size", "width height", "applyQualityOptions, over the scene's size"},
        {"--spp", "spp", "applyQualityOptions"},
        {"--depth", "depth", "applyQualityOptions"},
        {"--min-weight", "min_weight", "applyQualityOptions"},
        {"--indirect", "indirect", "applyQualityOptions"},
        {"--bounce", "bounce bounce_moving", "applyQualityOptions"},
        {"--tonemap", "tonemap", "applyQualityOptions"},
        {"--exposure", "exposure", "the EV given, or the one metered for the film with auto"},
        {"--fps", "timeline_fps", "the timeline's rate: which instant a frame index shows"},
        {"--background", "background", "transparent or a colour: the frames' pixels and alpha"},
        {"--frames-format", "frames_format", "exr: a linear frame kept beside each PNG, which --resume needs"},
        {"--environment", "environment", "the environment image (its bytes are in the input digests too)"},
        {"--environment-rotation", "environment_rotation", "SceneOptions"},
        {"--environment-intensity", "environment_intensity", "SceneOptions"},
        {"--ground", "ground", "SceneOptions"},
        {"--animation", "animation", "SceneOptions: which animation plays"},
        {"--camera", "camera", "SceneOptions: the glTF camera the film looks through"},
        {"--scene", "gltf_scene", "SceneOptions: which of the glTF file's scenes is drawn"},
        {"--variant", "variant", "SceneOptions: the materials shown"},
        {"--max-texture-size", "max_texture_size", "SceneOptions: textures downsampled on load"},
        {"--point-size", "point_size", "SceneOptions: how wide glTF points and lines are drawn"},
        // No pixel changes: where files go, how the video is encoded, how the work is spread.
        {"-o", nullptr, "the video: encoded again from the frames on every run"},
        {"--mode", nullptr, "a frame is bit-identical in pixel and frame mode"},
        {"--frames", nullptr, "which frames are rendered; a frame's file is named by its timeline index"},
        {"--frames-dir", nullptr, "where the frames are kept"},
        {"--no-frames", nullptr, "keeps no frames (and refuses --resume)"},
        {"--crf", nullptr, "the video's encoding only"},
        {"--preset", nullptr, "the video's encoding only"},
        {"--codec", nullptr, "the video's encoding only"},
        {"--lossless", nullptr, "the video's encoding only"},
        {"--chunk-frames", nullptr, "the video's encoding only"},
        {"--stats", nullptr, "a report of the run"},
        {"--contact-sheet", nullptr, "made from the frames"},
        {"--poster", nullptr, "made from a frame"},
        {"--poster-frame", nullptr, "which frame the poster shows"},
        {"--threads", nullptr, "a frame is bit-identical at any thread count"},
        {"--timeout", nullptr, "how long a silent worker is waited for"},
        {"--max-frame-failures", nullptr, "when a run gives up on a frame"},
        {"--asset-root", nullptr, "only limits where files may come from; the files read are in the input digests"},
        {"--preview", nullptr, "a window on the frames"},
        {"--resume", nullptr, "how the run starts"},
        {"--overwrite", nullptr, "how the run starts"},
        {"--help", nullptr, "prints the help"},
        {"-h", nullptr, "prints the help"},
    };
    return roles;
}

namespace {

/// An option's value with {name} replaced by the film's name ("" when the option is not given).
std::string forFilm(const ArgParser& p, const char* option, const std::string& name) {
    std::string v = p.value(option).value_or("");
    for (size_t at; (at = v.find("{name}")) != std::string::npos;) v.replace(at, 6, name);
    return v;
}

}  // namespace

std::string filmName(const std::string& scenePath) { return std::filesystem::path(scenePath).stem().string(); }

std::vector<farm::RenderJob> jobsFromOptions(const ArgParser& p) {
    const std::vector<std::string>& scenes = p.positional();
    if (scenes.empty()) throw UsageError("render: expected a SCENE or MODEL (see rayfarm render --help)");
    if (scenes.size() == 1) return {jobFromOptions(p, scenes[0], filmName(scenes[0]))};  // {name} with one scene too
    // Several films: every file a film writes must be its own.
    for (const char* o : {"-o", "--frames-dir", "--stats", "--contact-sheet", "--poster"}) {
        const auto v = p.value(o);
        if (v && v->find("{name}") == std::string::npos)
            throw UsageError(std::string(o) + " " + *v + ": with " + std::to_string(scenes.size()) +
                             " scenes, it must hold {name} (each film's name), e.g. -o 'out/{name}.mp4'");
    }
    std::vector<farm::RenderJob> jobs;
    for (const std::string& scene : scenes) {
        const std::string name = filmName(scene);
        for (const farm::RenderJob& j : jobs)
            if (filmName(j.scenePath) == name)
                throw UsageError("render: " + j.scenePath + " and " + scene + " would both be the film \"" + name +
                                 "\" ({name} is the file's name without its extension)");
        jobs.push_back(jobFromOptions(p, scene, name));
    }
    return jobs;
}

farm::RenderJob jobFromOptions(const ArgParser& p, const std::string& scene, const std::string& name) {
    farm::RenderJob j;
    j.scenePath = scene;
    if (!p.value("-o")) throw UsageError("render: -o out.mp4 is required");
    j.output = forFilm(p, "-o", name);
    try {
        farm::containerFor(j.output);
    } catch (const std::invalid_argument& e) {
        throw UsageError(j.output + ": " + e.what());
    }
    if (p.has("--no-frames") && p.has("--frames-dir")) throw UsageError("--no-frames and --frames-dir contradict each other");
    if (p.has("--resume") && p.has("--overwrite")) throw UsageError("--resume and --overwrite contradict each other");
    if (p.has("--no-frames") && p.has("--resume")) throw UsageError("--resume needs the frames directory (drop --no-frames)");
    if (p.has("--no-frames") && p.has("--preview")) throw UsageError("--preview shows the PNG frames as they complete (drop --no-frames)");
    if (!p.has("--no-frames"))
        // The output's whole name: out.webm and out.gif of one run each keep their own frames.
        j.framesDir = p.has("--frames-dir") ? forFilm(p, "--frames-dir", name) : j.output + ".frames";
    j.statsPath = forFilm(p, "--stats", name);
    j.sceneOptions = sceneOptions(p);  // checked here, where every rank parses, before the scene is shared
    j.modeOption = p.value("--mode").value_or("auto");
    if (j.modeOption != "auto" && j.modeOption != "pixel" && j.modeOption != "frame")
        throw UsageError("--mode: expected pixel, frame or auto, got \"" + j.modeOption + "\"");
    j.resume = p.has("--resume");
    // Ranges and names per format are checked by videoFormatFor once the alpha is known.
    j.mp4.crf = p.intValue("--crf", -1, 0, 63);
    j.mp4.preset = p.value("--preset").value_or("");
    j.mp4.codec = p.value("--codec").value_or("");
    j.mp4.lossless = p.has("--lossless");
    if (j.mp4.lossless && p.has("--crf")) throw UsageError("--lossless and --crf contradict each other");
    j.chunkFramesOption = p.intValue("--chunk-frames", 0, 1, 1 << 30);
    if (p.has("--chunk-frames") && j.chunkFramesOption < farm::kMinChunkFrames)
        throw UsageError("--chunk-frames: expected 2 or more (a chunk starts with a key frame: chunks of one frame would make "
                         "consecutive H.264 IDR pictures share idr_pic_id 0)");
    if (auto b = p.value("--background")) j.background = parseBackground(*b);
    const std::string framesFormat = p.value("--frames-format").value_or("png");
    if (framesFormat != "png" && framesFormat != "exr") throw UsageError("--frames-format: expected png or exr, got \"" + framesFormat + "\"");
    j.exrFrames = framesFormat == "exr";
    if (j.exrFrames && j.framesDir.empty()) throw UsageError("--frames-format exr needs the frames directory (drop --no-frames)");
    j.contactSheet = forFilm(p, "--contact-sheet", name);
    j.poster = forFilm(p, "--poster", name);
    for (const std::string* png : {&j.contactSheet, &j.poster})
        if (!png->empty() && std::filesystem::path(*png).extension() != ".png")
            throw UsageError(*png + ": expected a .png file name");
    j.posterFrame = p.intValue("--poster-frame", -1, 0, 1 << 30);
    if (j.posterFrame >= 0 && j.poster.empty()) throw UsageError("--poster-frame needs --poster FILE.png");
    j.threads = p.intValue("--threads", 0, 1, 4096);
    j.workerTimeout = p.doubleValue("--timeout", 10.0);
    if (!(j.workerTimeout >= 0.5 && j.workerTimeout <= 86400)) throw UsageError("--timeout: expected seconds from 0.5 to 86400");
    j.maxFrameFailures = p.intValue("--max-frame-failures", 3, 1, 1 << 20);
    if (p.has("--fps")) {
        j.fpsOption = p.doubleValue("--fps", 30.0);
        if (!anim::fpsInRange(j.fpsOption)) throw UsageError(std::string("--fps: ") + anim::kFpsRangeText);
    }
    return j;
}

void parseFrameRange(const std::string& text, int n, int& first, int& last) {
    auto bad = [&] {
        return UsageError("--frames: expected A:B with 0 ≤ A ≤ B ≤ " + std::to_string(n - 1) +
                               " (the timeline has " + std::to_string(n) + " frames), got \"" + text + "\"");
    };
    auto num = [&](const std::string& s, int def) {
        if (s.empty()) return def;
        size_t used = 0;
        int v = 0;
        try {
            v = std::stoi(s, &used);
        } catch (const std::exception&) {
            throw bad();
        }
        if (used != s.size()) throw bad();
        return v;
    };
    const size_t colon = text.find(':');
    if (colon == std::string::npos) {
        first = last = num(text, -1);
    } else {
        first = num(text.substr(0, colon), 0);
        last = num(text.substr(colon + 1), n - 1);
    }
    if (first < 0 || last < first || last >= n) throw bad();
}

}  // namespace rf::cli
