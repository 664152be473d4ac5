#pragma once
/// The quality report as a whole: reference render, sweep, and the files in the output folder
/// (report.csv, error_vs_time.png/.gp, summary.md, reference.png, default.png, error_default.png).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "farm/report/report_sweep.h"
#include "farm/report/report_video.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"
#include "anim/timeline.h"

namespace rf::report {

/// An image made elsewhere, a Cycles render for instance, that the sweep is scored against
/// instead of a reference rendered here: 8-bit sRGB as a viewer sees it.
struct ExternalReference {
    std::string path;
    int width = 0, height = 0;
    std::vector<uint8_t> rgb8;
};

/// Reads path (PNG or any stb-readable image) as 8-bit RGB; throws InputError naming path if it
/// cannot be read.
/// maxSide: a reference wider or taller (read from its header, before decoding) is refused.
ExternalReference readExternalReference(const std::string& path, int maxSide = 8192);

struct QualityReportOptions {
    std::string outDir;
    std::string sceneName;  ///< for titles
    int frame = 0;          ///< the frame index the scene is already posed at (seeds samples)
    int threads = 0;        ///< 0: all cores
    double targetPsnr = 30.0;
    SweepSpec sweep;
    QualitySetting reference{256, 16, 0.f};
    /// If set, the sweep is scored against this image (of the settings' size) and no reference
    /// is rendered: `reference` is unused and reference.png is not written.
    std::optional<ExternalReference> external;
    bool plot = true;      ///< draw error_vs_time.png with gnuplot
    bool progress = true;  ///< one line per render on stderr
    /// The report's bounce cache (RenderView::bounceSlot): its renders, and the metering before
    /// them, build it once for as long as the geometry, lights and bounce points stay the same.
    std::shared_ptr<SceneCacheSlot> bounceSlot = std::make_shared<SceneCacheSlot>();
};

struct QualityReport {
    SweepRow reference;
    std::vector<SweepRow> rows;
    std::vector<std::string> rayNotes;
    std::string csvPath, plotPath, summaryPath, errorImagePath, referencePath;
};

struct VideoReportOptions {
    std::string outDir;
    int frames = 24;  ///< from frame 0 of the timeline, at most its frame count
    int threads = 0;
    VideoSweepSpec sweep;
    bool plot = true;
    bool progress = true;
    /// Called after the timeline poses each frame (e.g. to look through a glTF camera).
    std::function<void(Scene&)> pose;
    /// The report's bounce cache (RenderView::bounceSlot): its renders, and the metering before
    /// them, build it once for as long as the geometry, lights and bounce points stay the same.
    std::shared_ptr<SceneCacheSlot> bounceSlot = std::make_shared<SceneCacheSlot>();
};

struct VideoReport {
    std::vector<VideoRow> rows;
    int frames = 0;
    std::string csvPath, plotPath;
};

/// Renders the first frames of the timeline at settings, runs the video sweep on them, writes
/// video.csv and video_psnr_vs_fps.png, and appends its section to summaryPath (if not empty).
/// Leaves the scene posed at the last frame rendered.
VideoReport runVideoReport(Scene& scene, const anim::Timeline& timeline, const RenderSettings& settings,
                           const VideoReportOptions& options, const std::string& summaryPath);

/// Renders the reference (or takes options.external) and the sweep of `scene` (posed at
/// options.frame, settings giving the image size and tone mapping) and writes every file.
/// Throws std::runtime_error on I/O failure, InputError if the external reference's size is not
/// the settings'.
QualityReport runQualityReport(const Scene& scene, const RenderSettings& settings, const QualityReportOptions& options);

}  // namespace rf::report
