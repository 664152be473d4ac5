#pragma once
/// summary.md of `rayfarm report`: the cheapest setting within the requested error, the default
/// setting's error, the Pareto front, and which ray kinds the scene never needed.
#include <string>
#include <vector>

#include "farm/report/report_sweep.h"
#include "engine/scene/scene.h"

namespace rf::report {

/// The fastest row whose PSNR is at least targetPsnr, or nullptr if none is.
const SweepRow* cheapestWithin(const std::vector<SweepRow>& rows, double targetPsnr);

/// One sentence per ray kind that was never traced in `rays` (primary, shadow, reflection,
/// refraction), saying what the scene leaves out: no lights, no light casting shadows, no
/// reflective or no transmissive material, or such surfaces out of view.
std::vector<std::string> missingRayKinds(const RayStats& rays, const Scene& scene);

struct SummaryInfo {
    std::string sceneName;
    int frame = 0;
    int width = 0, height = 0;
    int threads = 0;
    SweepKind kind = SweepKind::OneFactor;
    SweepRow reference;
    bool externalReference = false;  ///< the reference is an image from elsewhere (referenceImageFile)
    RayStats rays;  ///< what the ray notes went by: the reference render's, or the most of each kind in the sweep
    double targetPsnr = 30.0;
    std::string csvFile, plotFile, errorImageFile, referenceImageFile;
    double errorScale = 0.0;  ///< error shown as full red in the error image (99th percentile)
    std::vector<std::string> rayNotes;
};

/// The whole summary as Markdown.
std::string summaryMarkdown(const SummaryInfo& info, const std::vector<SweepRow>& rows);

/// Writes summaryMarkdown to path; throws std::runtime_error naming the path on failure.
void writeSummary(const std::string& path, const SummaryInfo& info, const std::vector<SweepRow>& rows);

}  // namespace rf::report
