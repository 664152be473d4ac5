// rayfarm report: error against run time for the quality settings, and the stiff-case table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "farm/cli/background_option.h"
#include "engine/integrators/bounce_cache.h"
#include "farm/cli/cli.h"
#include "farm/report/cmd_report.h"
#include "engine/util/errors.h"
#include "farm/cli/exposure_meter.h"
#include "engine/load/gltf/gltf_loader.h"
#include "farm/output/mp4_sink.h"
#include "farm/output/output_check.h"
#include "farm/report/report_csv.h"
#include "farm/report/report_plot.h"
#include "farm/report/report_run.h"
#include "farm/report/report_stability.h"
#include "engine/util/sample_count.h"
#include "engine/load/scene_loader.h"
#include "anim/timeline.h"

namespace rf::cli {

namespace {
const char* kReportHelpHead =
    "usage: rayfarm report SCENE|MODEL --out DIR [options]\n"
    "       rayfarm report SCENE|MODEL --reference FILE.png --out DIR [options]\n"
    "       rayfarm report --stability --out DIR [--threads N]\n"
    "\n"
    "Renders a reference of one frame (many samples, deep recursion, no pruning), then a sweep of\n"
    "quality settings, timing each render and scoring it against the reference (RMSE, PSNR, max\n"
    "error, SSIM on the tone-mapped 8-bit sRGB image). Writes to DIR: report.csv (every render),\n"
    "error_vs_time.png (log-log, Pareto front marked; gnuplot script beside it), summary.md (the\n"
    "cheapest setting within --target-psnr, the ray kinds the scene never needed), reference.png,\n"
    "default.png and error_default.png (false-colour error of the default setting).\n"
    "\n"
    "  --out DIR               output folder (created if needed)\n"
    "  --reference FILE.png    score every setting against this image instead (a Cycles render of\n"
    "                          the same camera, say); nothing is rendered as the reference and no\n"
    "                          reference.png is written. The render takes the image's size; a --size\n"
    "                          that differs is refused, and so are --ref-spp and --ref-depth\n"
    "  --frame N               frame of the scene's timeline (default 0)\n"
    "  --camera N              look through the model's glTF camera N (posed by its animation)\n"
    "  --size WxH              image size (default: the scene's)\n"
    "  --target-psnr DB        the error the summary answers for (default 30)\n"
    "  --threads N             worker threads (default: all cores)\n"
    "  --spp N, --depth N, --min-weight W, --indirect N, --bounce N, --tonemap T, --exposure EV|auto\n"
    "                          the default setting the sweep is centred on (default: the scene's)\n"
    "  --environment F, --environment-rotation DEG, --environment-intensity K, --ground G, --background B,\n"
    "  --animation A\n"
    "                          the picture, as rayfarm still takes them (--background: a colour)\n"
    "  --asset-root DIR, --max-texture-size N   glTF asset folder and texture size, as for still\n"
    "  --point-size PX   how wide glTF points and lines are drawn, as for still\n"
    "  --variant NAME          the model's material variant NAME, as for still\n"
    "  --grid ofat|full        one factor at a time around the default (ofat, default) or every\n"
    "                          combination (full: the product of the lists' lengths)\n";

const char* kReportHelpTail =
    "  --ref-spp N             reference samples per pixel, a square (default 256)\n"
    "  --ref-depth N           reference maximum depth (default 16)\n"
    "\n"
    "Then the video: the first --video-frames frames of the timeline, rendered at the default\n"
    "setting, are encoded by the MP4 sink at each preset and CRF, decoded, and scored against the\n"
    "lossless frames (PSNR, SSIM) next to the encoding speed: video.csv, video_psnr_vs_fps.png and a\n"
    "section of summary.md.\n"
    "\n"
    "  --no-video              skip the video part\n"
    "  --video-frames N        frames to encode (default 24, at most the timeline's)\n"
    "  --video-crf LIST        x264 CRF values (default 0,12,18,23,28,35)\n"
    "  --video-preset LIST     x264 presets (default ultrafast,veryfast,medium,slow)\n"
    "  --stability             instead: run the stiff and extreme cases of the stability catalogue and\n"
    "                          write stability.md and stability.csv (measured error, pass/fail);\n"
    "                          exit status 1 if a case fails\n";

/// The help text, with one --sweep-NAME line per knob of the sweep.
std::string reportHelp() {
    std::string s = kReportHelpHead;
    for (const report::QualityKnob& k : report::qualityKnobs()) {
        std::string line = "  " + report::sweepOption(k) + " LIST";
        line.resize(std::max<size_t>(line.size() + 1, 26), ' ');
        line += k.meaning;
        line += k.values == report::KnobValues::Square ? " to sweep, squares (default " : " to sweep (default ";
        for (size_t i = 0; i < k.sweep.size(); ++i) {
            if (i) line += ',';
            line += report::formatNumber(k.sweep[i]);
        }
        s += line + ")\n";
    }
    return s + kReportHelpTail;
}

std::vector<std::string> splitList(const std::string& name, const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(item);
    if (out.empty()) throw UsageError(name + ": expected a comma-separated list, got \"" + text + "\"");
    return out;
}

std::vector<int> intList(const ArgParser& p, const std::string& name, std::vector<int> def, int lo, int hi,
                         bool squares) {
    const auto v = p.value(name);
    if (!v) return def;
    std::vector<int> out;
    for (const std::string& s : splitList(name, *v)) {
        size_t used = 0;
        int x = 0;
        try {
            x = std::stoi(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != s.size() || x < lo || x > hi || (squares && !isSquareSpp(x)))
            throw UsageError(name + ": expected " + (squares ? "square " : "") + "integers from " +
                             std::to_string(lo) + " to " + std::to_string(hi) + ", got \"" + s + "\"");
        out.push_back(x);
    }
    return out;
}

/// A --sweep-NAME list, checked against what the knob takes.
std::vector<double> knobList(const ArgParser& p, const report::QualityKnob& k, std::vector<double> def) {
    const std::string name = report::sweepOption(k);
    const auto v = p.value(name);
    if (!v) return def;
    std::vector<double> out;
    for (const std::string& s : splitList(name, *v)) {
        size_t used = 0;
        double x = std::nan("");
        try {
            x = std::stod(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        const bool whole = k.values != report::KnobValues::Fraction;
        const bool ok = used != 0 && used == s.size() && x >= k.lo && x <= k.hi && (!whole || x == std::floor(x)) &&
                        (k.values != report::KnobValues::Square || isSquareSpp(int(x)));
        if (!ok)
            throw UsageError(name + ": expected " +
                             (k.values == report::KnobValues::Square ? "square integers"
                              : whole                                ? "integers"
                                                                     : "numbers") +
                             " from " + report::formatNumber(k.lo) + " to " + report::formatNumber(k.hi) + ", got \"" +
                             s + "\"");
        out.push_back(x);
    }
    return out;
}

/// report --stability: the catalogue's cases to stability.md and .csv; status 1 if one fails.
int runStabilityCommand(const ArgParser& p, const std::string& out, int threads) {
    if (!p.positional().empty()) throw UsageError("report --stability: takes no SCENE");
    ensureWritableDir(out);
    const report::StabilityReport rep = report::runStabilityReport(out, threads);
    std::fprintf(stderr, "rayfarm: report: %d of %d stability cases pass; wrote %s and %s\n", rep.passed(),
                 rep.counted(), rep.markdownPath.c_str(), rep.csvPath.c_str());
    return rep.passed() == rep.counted() ? 0 : 1;  // scripts and CI can act on a failing case
}

/// The sweep and reference options (not yet the base settings, which need the scene).
report::QualityReportOptions qualityOptions(const ArgParser& p, const std::string& out, int threads,
                                            const std::string& scenePath) {
    report::QualityReportOptions o;
    o.outDir = out;
    o.threads = threads;
    o.targetPsnr = p.doubleValue("--target-psnr", 30.0);
    if (!(o.targetPsnr > 0.0 && o.targetPsnr <= 200.0)) throw UsageError("--target-psnr: expected dB above 0, up to 200");
    o.sceneName = std::filesystem::path(scenePath).filename().string();
    const auto& knobs = report::qualityKnobs();
    for (size_t k = 0; k < knobs.size(); ++k) o.sweep.lists[k] = knobList(p, knobs[k], o.sweep.lists[k]);
    if (auto g = p.value("--grid")) {
        if (*g == "full") o.sweep.kind = report::SweepKind::FullGrid;
        else if (*g != "ofat") throw UsageError("--grid: expected ofat or full, got \"" + *g + "\"");
    }
    const int refSpp = p.intValue("--ref-spp", 256, 1, 65536);
    if (const std::string e = sppProblem(refSpp); !e.empty()) throw UsageError("--ref-spp: " + e);
    o.reference.setValue("spp", refSpp);
    o.reference.setValue("depth", p.intValue("--ref-depth", 16, 1, 64));
    o.reference.setValue("min_weight", 0.0);
    if (auto r = p.value("--reference")) {
        for (const char* opt : {"--ref-spp", "--ref-depth"})
            if (p.has(opt)) throw UsageError(std::string(opt) + ": no reference is rendered with --reference");
        // A bad file stops the run here, before rendering; its size is checked from its header.
        o.external = report::readExternalReference(*r, sceneOptions(p).assets.maxTextureSize);
    }
    return o;
}

report::VideoReportOptions videoOptions(const ArgParser& p, const std::string& out, int threads) {
    report::VideoReportOptions vo;
    vo.outDir = out;
    vo.threads = threads;
    vo.frames = p.intValue("--video-frames", vo.frames, 1, 100000);
    vo.sweep.crf = intList(p, "--video-crf", vo.sweep.crf, 0, 51, false);
    if (auto v = p.value("--video-preset")) vo.sweep.presets = splitList("--video-preset", *v);
    return vo;
}

/// Refuses a preset the encoder does not know before any rendering; notes the padding once.
void checkVideoPresets(const report::VideoReportOptions& vo, const RenderSettings& settings) {
    for (const std::string& preset : vo.sweep.presets) {
        farm::Mp4Options mo;
        mo.preset = preset;
        try {
            const std::string note = checkMp4Options(settings.width, settings.height, mo);
            if (!note.empty() && preset == vo.sweep.presets.front())
                std::fprintf(stderr, "rayfarm: note: video sweep: %s\n", note.c_str());
        } catch (const std::invalid_argument& e) {
            throw UsageError(std::string("--video-preset: ") + e.what());
        }
    }
}

/// The scene at --frame, checked against its timeline (which looks through --camera), over --background.
Scene sceneAtFrame(const ArgParser& p, const std::string& scenePath, anim::Timeline& timeline, int& frame) {
    BackgroundChoice background;
    if (auto b = p.value("--background")) background = parseBackground(*b);
    // The scores are of the opaque picture a viewer sees; an alpha plane has no counterpart there.
    if (background.kind == BackgroundChoice::Transparent)
        throw UsageError("--background: report scores an opaque picture; give a colour, not transparent");
    DiskFileSource fs;
    LoadedScene loaded = loadScene(scenePath, fs, sceneOptions(p));
    Scene& scene = loaded.scene;
    for (const std::string& note : scene.notes) std::fprintf(stderr, "rayfarm: note: %s\n", note.c_str());
    applyBackground(background, scene);
    timeline = anim::Timeline::fromScene(loaded);
    frame = p.intValue("--frame", 0, 0, 1 << 30);
    if (frame >= timeline.frameCount())
        throw UsageError("--frame: " + scenePath + " has " + std::to_string(timeline.frameCount()) +
                         " frame(s), numbered from 0; got " + std::to_string(frame));
    timeline.applyFrame(scene, frame);
    return std::move(scene);
}

/// The default setting the sweep is centred on; with --reference, at the reference's size.
RenderSettings baseSettings(const ArgParser& p, Scene& scene, const anim::Timeline& timeline,
                            const report::QualityReportOptions& o, int threads) {
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    if (o.external) {
        const report::ExternalReference& ref = *o.external;
        if (p.has("--size") && (settings.width != ref.width || settings.height != ref.height))
            throw InputError(ref.path, "is " + std::to_string(ref.width) + "x" + std::to_string(ref.height) +
                                           " but --size asks for " + std::to_string(settings.width) + "x" +
                                           std::to_string(settings.height) +
                                           " (leave --size out: the render takes the reference's size)");
        settings.width = ref.width;
        settings.height = ref.height;
    }
    resolveAutoExposure(scene, timeline, settings, threads, {}, o.bounceSlot);
    return settings;
}

}  // namespace

int runReport(const std::vector<std::string>& args) {
    ArgParser p("report");
    for (const char* o : {"--out", "--frame", "--size", "--target-psnr", "--threads", "--spp", "--depth",
                          "--min-weight", "--indirect", "--bounce", "--tonemap", "--exposure", "--grid", "--ref-spp", "--ref-depth",
                          "--reference", "--background", "--video-frames", "--video-crf",
                          "--video-preset"})
        p.option(o);
    for (const report::QualityKnob& k : report::qualityKnobs()) p.option(report::sweepOption(k));
    declareSceneOptions(p);
    for (const char* f : {"--stability", "--no-video", "--help", "-h"}) p.flag(f);
    p.parse(args);
    if (p.has("--help") || p.has("-h")) {
        std::fputs(reportHelp().c_str(), stdout);
        return 0;
    }
    const auto out = p.value("--out");
    if (!out) throw UsageError("report: --out DIR is required (see rayfarm report --help)");
    const int threads = p.intValue("--threads", 0, 1, 4096);
    if (p.has("--stability")) return runStabilityCommand(p, *out, threads);

    if (p.positional().size() != 1) throw UsageError("report: expected one SCENE or MODEL (see rayfarm report --help)");
    const std::string scenePath = p.positional()[0];
    report::QualityReportOptions o = qualityOptions(p, *out, threads, scenePath);
    report::VideoReportOptions vo = videoOptions(p, *out, threads);
    vo.bounceSlot = o.bounceSlot;  // one bounce cache for the metering, the sweep and the video
    // Fail before hours of rendering, not after.
    if (report::findOnPath("gnuplot").empty())
        throw std::runtime_error("report: gnuplot not found on PATH (install the Debian package gnuplot-nox)");
    ensureWritableDir(*out);

    anim::Timeline timeline;
    Scene scene = sceneAtFrame(p, scenePath, timeline, o.frame);
    const RenderSettings settings = baseSettings(p, scene, timeline, o, threads);
    o.sweep.base = report::qualityOf(settings);
    // Bounce light lights only glTF materials of a scene with lights or emission: elsewhere its
    // line would render the same picture four times over. Leave it out unless asked for.
    if (!p.value("--sweep-bounce") && !bounceApplies(scene))
        o.sweep.list("bounce") = {double(settings.bounce)};
    const bool video = !p.has("--no-video");
    if (video) checkVideoPresets(vo, settings);

    const report::QualityReport rep = report::runQualityReport(scene, settings, o);
    std::fprintf(stderr, "rayfarm: report: %d renders; wrote %s, %s, %s\n", int(rep.rows.size()) + 1,
                 rep.csvPath.c_str(), rep.plotPath.c_str(), rep.summaryPath.c_str());
    if (video) {
        const report::VideoReport vr = report::runVideoReport(scene, timeline, settings, vo, rep.summaryPath);
        std::fprintf(stderr, "rayfarm: report: %d encodes of %d frames; wrote %s, %s\n", int(vr.rows.size()), vr.frames,
                     vr.csvPath.c_str(), vr.plotPath.c_str());
    }
    return 0;
}

}  // namespace rf::cli
