#include "farm/report/report_run.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "engine/util/errors.h"
#include "engine/util/image.h"
#include "engine/util/image_metrics.h"
#include "engine/integrators/render.h"
#include "farm/report/report_csv.h"
#include "farm/report/report_plot.h"
#include "farm/report/report_summary.h"

namespace rf::report {

namespace {

/// Renders the reference once (the slowest render by far; its time is only for orientation),
/// writes reference.png and fills rep.reference; returns its 8-bit pixels.
std::vector<uint8_t> renderReference(const Scene& scene, const RenderSettings& settings, const QualityReportOptions& o,
                                     QualityReport& rep) {
    const int w = settings.width, h = settings.height;
    if (o.progress)
        std::fprintf(stderr, "rayfarm: report: reference %s at %dx%d ...\n", describe(o.reference).c_str(), w, h);
    const RenderSettings refSettings = withQuality(settings, o.reference);
    const TimedRender ref = renderTimed(scene, refSettings, o.frame, o.threads, 0.0, 1, o.bounceSlot);
    const std::vector<uint8_t> ref8 = toRgb8(ref.image, settings);
    writePng(rep.referencePath, w, h, ref8);
    rep.reference.q = o.reference;
    rep.reference.factor = "reference";
    rep.reference.seconds = ref.seconds;
    rep.reference.repeats = ref.repeats;
    rep.reference.rays = ref.rays;
    rep.reference.error = compareRgb8(ref8, ref8, w, h);
    if (o.progress) std::fprintf(stderr, "rayfarm: report: reference took %.2f s\n", ref.seconds);
    return ref8;
}

/// Takes the external reference as the reference row (no setting, no time, no rays); returns
/// its pixels.
std::vector<uint8_t> takeExternalReference(const RenderSettings& settings, const QualityReportOptions& o,
                                           QualityReport& rep) {
    const ExternalReference& ext = *o.external;
    if (ext.width != settings.width || ext.height != settings.height)
        throw InputError(ext.path, "is " + std::to_string(ext.width) + "x" + std::to_string(ext.height) +
                                       "; the render is " + std::to_string(settings.width) + "x" +
                                       std::to_string(settings.height));
    rep.referencePath = ext.path;
    rep.reference.q = qualityOf(settings);
    rep.reference.factor = "reference";
    rep.reference.external = true;
    rep.reference.error = compareRgb8(ext.rgb8, ext.rgb8, ext.width, ext.height);
    if (o.progress)
        std::fprintf(stderr, "rayfarm: report: scoring against %s (%dx%d)\n", ext.path.c_str(), ext.width, ext.height);
    return ext.rgb8;
}

/// The most rays of each kind any one render traced: what the ray-kind notes go by when no
/// reference was rendered here.
RayStats mostRaysOfEachKind(const std::vector<SweepRow>& rows) {
    RayStats m;
    for (const SweepRow& r : rows) {
        m.primary = std::max(m.primary, r.rays.primary);
        m.shadow = std::max(m.shadow, r.rays.shadow);
        m.reflection = std::max(m.reflection, r.rays.reflection);
        m.refraction = std::max(m.refraction, r.rays.refraction);
    }
    return m;
}

/// Renders the default setting to default.png and its error against the reference, in false
/// colour, to errorImagePath; returns the error scale used.
double writeDefaultImages(const Scene& scene, const RenderSettings& settings, const QualityReportOptions& o,
                          const std::vector<uint8_t>& ref8, const std::string& errorImagePath) {
    const int w = settings.width, h = settings.height;
    const std::filesystem::path dir(o.outDir);
    const RenderSettings defSettings = withQuality(settings, o.sweep.base);
    RayStats rays;
    const Image def = renderFrame(scene, {scene.camera, defSettings, o.bounceSlot}, o.frame, o.threads, rays);
    const std::vector<uint8_t> def8 = toRgb8(def, settings);
    writePng((dir / "default.png").string(), w, h, def8);
    // Scaled to the 99th percentile, so a few extreme pixels do not leave the rest black.
    const double scale = std::max(errorQuantileRgb8(def8, ref8, w, h, 0.99), 1.0 / 255.0);
    writePng(errorImagePath, w, h, falseColorErrorRgb8(def8, ref8, w, h, scale));
    return scale;
}

}  // namespace

ExternalReference readExternalReference(const std::string& path, int maxSide) {
    ExternalReference ext;
    ext.path = path;
    if (std::FILE* f = std::fopen(path.c_str(), "rb"))
        std::fclose(f);
    else
        throw InputError(path, std::string("cannot open the reference image: ") + std::strerror(errno));
    int w = 0, h = 0;
    if (readImageSize(path, w, h) && (w > maxSide || h > maxSide))
        throw InputError(path, "the reference image declares " + std::to_string(w) + "x" + std::to_string(h) + ", over " +
                                   std::to_string(maxSide) + " on a side (--max-texture-size); nothing was decoded");
    try {
        ext.rgb8 = readImageRgb8(path, ext.width, ext.height);
    } catch (const std::runtime_error&) {
        // readImageRgb8's message names the path and stb's terse reason; say what the file was for.
        throw InputError(path, "not a readable reference image (expected a PNG; truncated or another format?)");
    }
    return ext;
}

QualityReport runQualityReport(const Scene& scene, const RenderSettings& settings, const QualityReportOptions& o) {
    namespace fs = std::filesystem;
    const fs::path dir(o.outDir);
    QualityReport rep;
    rep.csvPath = (dir / "report.csv").string();
    rep.plotPath = (dir / "error_vs_time.png").string();
    rep.summaryPath = (dir / "summary.md").string();
    rep.errorImagePath = (dir / "error_default.png").string();
    rep.referencePath = (dir / "reference.png").string();
    const int w = settings.width, h = settings.height;

    const std::vector<uint8_t> ref8 =
        o.external ? takeExternalReference(settings, o, rep) : renderReference(scene, settings, o, rep);
    auto progress = [&](int i, int n, const SweepRow& r) {
        if (o.progress)
            std::fprintf(stderr, "rayfarm: report: [%d/%d] %s: %.4g s, PSNR %.2f dB, SSIM %.4f\n", i, n,
                         describe(r.q).c_str(), r.seconds, r.error.psnr, r.error.ssim);
    };
    rep.rows = runSweep(scene, settings, o.sweep, ref8, o.frame, o.threads, progress, o.bounceSlot);
    writeReportCsv(rep.csvPath, rep.reference, rep.rows);

    const double scale = writeDefaultImages(scene, settings, o, ref8, rep.errorImagePath);
    const std::string against = o.external ? " against " + fs::path(o.external->path).filename().string() : "";
    if (o.plot)
        plotErrorVsTime(rep.rows,
                        o.sceneName + ": error" + against + " against run time, " + std::to_string(w) + "x" +
                            std::to_string(h) + ", frame " + std::to_string(o.frame),
                        (dir / "error_vs_time.gp").string(), rep.plotPath);

    const RayStats rays = o.external ? mostRaysOfEachKind(rep.rows) : rep.reference.rays;
    rep.rayNotes = missingRayKinds(rays, scene);
    SummaryInfo info;
    info.sceneName = o.sceneName;
    info.frame = o.frame;
    info.width = w;
    info.height = h;
    info.threads = o.threads > 0 ? o.threads : hardwareThreads();
    info.kind = o.sweep.kind;
    info.reference = rep.reference;
    info.targetPsnr = o.targetPsnr;
    info.csvFile = "report.csv";
    info.plotFile = o.plot ? "error_vs_time.png" : "(not drawn)";
    info.errorImageFile = "error_default.png";
    info.referenceImageFile = o.external ? o.external->path : "reference.png";
    info.externalReference = o.external.has_value();
    info.rays = rays;
    info.errorScale = scale;
    info.rayNotes = rep.rayNotes;
    writeSummary(rep.summaryPath, info, rep.rows);
    return rep;
}

VideoReport runVideoReport(Scene& scene, const anim::Timeline& timeline, const RenderSettings& settings,
                           const VideoReportOptions& o, const std::string& summaryPath) {
    namespace fs = std::filesystem;
    const fs::path dir(o.outDir);
    VideoReport rep;
    rep.frames = std::max(1, std::min(o.frames, timeline.frameCount()));
    rep.csvPath = (dir / "video.csv").string();
    rep.plotPath = (dir / "video_psnr_vs_fps.png").string();
    const int w = settings.width, h = settings.height;
    if (o.progress) std::fprintf(stderr, "rayfarm: report: rendering %d frames for the video sweep ...\n", rep.frames);
    std::vector<std::vector<uint8_t>> frames;
    for (int i = 0; i < rep.frames; ++i) {
        timeline.applyFrame(scene, i);
        if (o.pose) o.pose(scene);
        RayStats rays;
        frames.push_back(
            toRgb8(renderFrame(scene, {scene.camera, settings, o.bounceSlot}, i, o.threads, rays), settings));
    }
    VideoSweepSpec spec = o.sweep;
    spec.fps = timeline.fps();
    rep.rows = runVideoSweep(frames, w, h, spec, (dir / "video_scratch.mp4").string(), [&](int i, int n, const VideoRow& r) {
        if (o.progress)
            std::fprintf(stderr, "rayfarm: report: video [%d/%d] %s crf %d: %.1f fps, PSNR %.2f dB, SSIM %.4f\n", i, n,
                         r.lossless ? "lossless" : r.preset.c_str(), r.crf, r.encodeFps, r.psnr, r.ssim);
    });
    writeVideoCsv(rep.csvPath, rep.rows);
    if (o.plot)
        runGnuplot(videoPlotScript(rep.rows, "encoded MP4 against lossless frames, " + std::to_string(rep.frames) +
                                                 " frames " + std::to_string(w) + "x" + std::to_string(h),
                                   rep.plotPath),
                   (dir / "video_psnr_vs_fps.gp").string(), rep.plotPath);
    if (!summaryPath.empty()) {
        std::ofstream f(summaryPath, std::ios::app);
        f << "\n" << videoMarkdown(rep.rows, rep.frames, w, h);
        if (!f.flush()) throw std::runtime_error(summaryPath + ": write failed");
    }
    return rep;
}

}  // namespace rf::report
