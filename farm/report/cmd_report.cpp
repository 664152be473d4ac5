// rayfarm report: error against run time for the quality settings, and the stiff-case table.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli.h"
#include "exposure_meter.h"
#include "sample_count.h"
#include "mp4_sink.h"
#include "output_check.h"
#include "report_plot.h"
#include "report_run.h"
#include "report_stability.h"
#include "scene_loader.h"
#include "timeline.h"

namespace rf::cli {

namespace {
const char* kReportHelp =
    "usage: rayfarm report SCENE|MODEL --out DIR [options]\n"
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
    "  --frame N               frame of the scene's timeline (default 0)\n"
    "  --size WxH              image size (default: the scene's)\n"
    "  --target-psnr DB        the error the summary answers for (default 30)\n"
    "  --threads N             worker threads (default: all cores)\n"
    "  --spp N, --depth N, --min-weight W, --tonemap T, --exposure EV|auto\n"
    "                          the default setting the sweep is centred on (default: the scene's)\n"
    "  --grid ofat|full        one factor at a time around the default (ofat, default) or every\n"
    "                          combination (full: |spp| x |depth| x |min weight| renders)\n"
    "  --sweep-spp LIST        samples per pixel to sweep, squares (default 1,4,16,64)\n"
    "  --sweep-depth LIST      maximum depths to sweep (default 1,2,3,4,5,6,7,8)\n"
    "  --sweep-min-weight LIST pruning thresholds to sweep (default 0,0.001,0.01,0.1)\n"
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

std::vector<float> weightList(const ArgParser& p, const std::string& name, std::vector<float> def) {
    const auto v = p.value(name);
    if (!v) return def;
    std::vector<float> out;
    for (const std::string& s : splitList(name, *v)) {
        size_t used = 0;
        double x = -1;
        try {
            x = std::stod(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != s.size() || !(x >= 0.0 && x <= 1.0))
            throw UsageError(name + ": expected numbers from 0 to 1, got \"" + s + "\"");
        out.push_back(static_cast<float>(x));
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
    if (!std::isfinite(o.targetPsnr)) throw UsageError("--target-psnr: expected a finite number of dB");
    o.sceneName = std::filesystem::path(scenePath).filename().string();
    o.sweep.spp = intList(p, "--sweep-spp", o.sweep.spp, 1, 4096, true);
    o.sweep.depth = intList(p, "--sweep-depth", o.sweep.depth, 1, 64, false);
    o.sweep.minWeight = weightList(p, "--sweep-min-weight", o.sweep.minWeight);
    if (auto g = p.value("--grid")) {
        if (*g == "full") o.sweep.kind = report::SweepKind::FullGrid;
        else if (*g != "ofat") throw UsageError("--grid: expected ofat or full, got \"" + *g + "\"");
    }
    o.reference.spp = p.intValue("--ref-spp", 256, 1, 65536);
    if (const std::string e = sppProblem(o.reference.spp); !e.empty()) throw UsageError("--ref-spp: " + e);
    o.reference.maxDepth = p.intValue("--ref-depth", 16, 1, 64);
    o.reference.minWeight = 0.f;
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

/// The scene at --frame, checked against its timeline.
Scene sceneAtFrame(const ArgParser& p, const std::string& scenePath, anim::Timeline& timeline, int& frame) {
    DiskFileSource fs;
    Scene scene = loadScene(scenePath, fs, sceneOptions(p));
    for (const std::string& note : scene.notes) std::fprintf(stderr, "rayfarm: note: %s\n", note.c_str());
    timeline = anim::Timeline::fromScene(scene);
    frame = p.intValue("--frame", 0, 0, 1 << 30);
    if (frame >= timeline.frameCount())
        throw UsageError("--frame: " + scenePath + " has " + std::to_string(timeline.frameCount()) +
                         " frame(s), numbered from 0; got " + std::to_string(frame));
    timeline.applyFrame(scene, frame);
    return scene;
}

}  // namespace

int runReport(const std::vector<std::string>& args) {
    ArgParser p("report");
    for (const char* o : {"--out", "--frame", "--size", "--target-psnr", "--threads", "--spp", "--depth",
                          "--min-weight", "--tonemap", "--exposure", "--grid", "--sweep-spp", "--sweep-depth", "--sweep-min-weight",
                          "--ref-spp", "--ref-depth", "--video-frames", "--video-crf", "--video-preset"})
        p.option(o);
    for (const char* f : {"--stability", "--no-video", "--help", "-h"}) p.flag(f);
    p.parse(args);
    if (p.has("--help") || p.has("-h")) {
        std::fputs(kReportHelp, stdout);
        return 0;
    }
    const auto out = p.value("--out");
    if (!out) throw UsageError("report: --out DIR is required (see rayfarm report --help)");
    const int threads = p.intValue("--threads", 0, 0, 4096);
    if (p.has("--stability")) return runStabilityCommand(p, *out, threads);

    if (p.positional().size() != 1) throw UsageError("report: expected one SCENE or MODEL (see rayfarm report --help)");
    const std::string scenePath = p.positional()[0];
    report::QualityReportOptions o = qualityOptions(p, *out, threads, scenePath);
    const report::VideoReportOptions vo = videoOptions(p, *out, threads);
    // Fail before hours of rendering, not after.
    if (report::findOnPath("gnuplot").empty())
        throw std::runtime_error("report: gnuplot not found on PATH (install the Debian package gnuplot-nox)");
    ensureWritableDir(*out);

    anim::Timeline timeline;
    Scene scene = sceneAtFrame(p, scenePath, timeline, o.frame);
    RenderSettings settings = scene.settings;
    applyQualityOptions(p, settings);
    resolveAutoExposure(scene, timeline, settings, p.intValue("--threads", 0, 0, 4096));
    o.sweep.base = {settings.spp, settings.maxDepth, settings.minWeight};
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
