#include "farm/report/report_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rf::report {

namespace {

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string psnrText(double db) { return std::isinf(db) ? "∞ dB" : fmt("%.2f dB", db); }

std::string rowCells(const SweepRow& r) {
    return "| " + describe(r.q) + (r.isDefault ? " (default)" : "") + " | " + r.factor + " | " +
           fmt("%.4g", r.seconds) + " | " + fmt("%.4g", r.error.rmse) + " | " + psnrText(r.error.psnr) + " | " +
           fmt("%.3f", r.error.maxError) + " | " + fmt("%.4f", r.error.ssim) + " | " +
           std::to_string(r.rays.total()) + " |\n";
}

/// Where the reference came from.
std::string referenceSentence(const SummaryInfo& in) {
    if (in.externalReference)
        return "Reference: `" + in.referenceImageFile + "`, an image made elsewhere (not rendered here), " +
               std::to_string(in.width) + "×" + std::to_string(in.height) + ". Renders ran on " +
               std::to_string(in.threads) + " thread(s).";
    return "Reference: " + describe(in.reference.q) + ", rendered in " + fmt("%.2f s", in.reference.seconds) + " on " +
           std::to_string(in.threads) + " thread(s) (`" + in.referenceImageFile + "`).";
}

/// How the sweep was laid out, in the knob table's words.
std::string sweepSentence(SweepKind kind) {
    const auto& knobs = qualityKnobs();
    std::string lines, others;
    for (size_t i = 0; i < knobs.size(); ++i) {
        lines += std::string(i == 0 ? "" : ", then the ") + knobs[i].meaning;
        if (i > 0) others += std::string(i == 1 ? "" : " × ") + "|" + knobs[i].meaning + "|";
    }
    if (kind == SweepKind::FullGrid) return "Full grid: every combination of " + lines + ".";
    return "One factor at a time around the default: " + lines +
           ", each with the others at their default. This costs about as much as the " + knobs[0].meaning +
           " line alone; the full grid (`--grid full`) renders every combination and costs about " + others +
           " times more.";
}

const char* kTableHead =
    "| setting | sweep | seconds | RMSE | PSNR | max error | SSIM | rays |\n"
    "|---|---|---:|---:|---:|---:|---:|---:|\n";

}  // namespace

const SweepRow* cheapestWithin(const std::vector<SweepRow>& rows, double targetPsnr) {
    const SweepRow* best = nullptr;
    for (const SweepRow& r : rows)
        if (r.error.psnr >= targetPsnr && (!best || r.seconds < best->seconds)) best = &r;
    return best;
}

std::vector<std::string> missingRayKinds(const RayStats& rays, const Scene& scene) {
    const SceneFeatures f = scene.features();
    std::vector<std::string> out;
    if (rays.primary == 0) out.push_back("No primary rays: the image has no pixels.");
    if (rays.shadow == 0) {
        if (scene.lights.empty())
            out.push_back("No shadow rays: the scene has no lights (only ambient and emission light it).");
        else if (!f.shadows)
            out.push_back("No shadow rays: no light in the scene casts shadows.");
        else
            out.push_back("No shadow rays: no lit surface is in view.");
    }
    if (rays.reflection == 0)
        out.push_back(f.reflection ? "No reflection rays: the reflective surfaces are out of view (or pruned)."
                                   : "No reflection rays: no material reflects (no mirrors).");
    if (rays.refraction == 0)
        out.push_back(f.transmission ? "No refraction rays: the transmissive surfaces are out of view (or pruned)."
                                     : "No refraction rays: no material transmits light (no glass).");
    return out;
}

std::string summaryMarkdown(const SummaryInfo& in, const std::vector<SweepRow>& rows) {
    std::ostringstream s;
    s << "# Error against run time: " << in.sceneName << ", frame " << in.frame << ", " << in.width << "×"
      << in.height << "\n\n";
    s << referenceSentence(in) << " Every setting below renders the "
      << "same frame and is scored against it on the tone-mapped 8-bit sRGB image a viewer sees: RMSE and largest "
      << "per-pixel channel error on the 0..1 scale, PSNR with peak 1, SSIM (Wang et al. 2004) on luma with an "
      << "11×11 Gaussian window (σ 1.5). Times are the fastest of up to nine renders of each setting, repeated round "
         "robin over all settings until a setting has had a second, since other work on the machine only ever adds "
         "time.\n\n";

    s << "## Cheapest setting within " << fmt("%g", in.targetPsnr) << " dB PSNR\n\n";
    if (const SweepRow* best = cheapestWithin(rows, in.targetPsnr)) {
        s << "**" << describe(best->q) << "**: " << fmt("%.4g s", best->seconds) << ", PSNR "
          << psnrText(best->error.psnr) << ", SSIM " << fmt("%.4f", best->error.ssim);
        if (!in.externalReference)
            s << ", " << fmt("%.1f×", in.reference.seconds / std::max(best->seconds, 1e-12))
              << " faster than the reference";
        s << ".\n\n";
    } else {
        const auto it = std::max_element(rows.begin(), rows.end(),
                                         [](const SweepRow& a, const SweepRow& b) { return a.error.psnr < b.error.psnr; });
        s << "No setting of the sweep reaches " << fmt("%g", in.targetPsnr) << " dB.";
        if (it != rows.end()) s << " The closest is " << describe(it->q) << " at " << psnrText(it->error.psnr) << ".";
        s << "\n\n";
    }

    for (const SweepRow& r : rows) {
        if (!r.isDefault) continue;
        s << "## The default setting\n\n" << describe(r.q) << " (the scene's own): " << fmt("%.4g s", r.seconds)
          << ", RMSE " << fmt("%.4g", r.error.rmse) << ", PSNR " << psnrText(r.error.psnr) << ", max error "
          << fmt("%.3f", r.error.maxError) << ", SSIM " << fmt("%.4f", r.error.ssim) << ". Where its error is: `"
          << in.errorImageFile << "` (largest channel difference per pixel; black 0, then blue, cyan, green, "
          << "yellow, red at " << fmt("%.3g", in.errorScale) << " — the 99th percentile — and above).\n\n";
    }

    s << "## Ray kinds\n\n"
      << (in.externalReference ? "Most rays of each kind in one render of the sweep" : "Reference render")
      << ": primary " << in.rays.primary << ", shadow " << in.rays.shadow << ", reflection " << in.rays.reflection
      << ", refraction " << in.rays.refraction << ".\n\n";
    if (in.rayNotes.empty()) s << "The scene uses every ray kind.\n\n";
    for (const std::string& n : in.rayNotes) s << "- " << n << "\n";
    if (!in.rayNotes.empty()) s << "\n";

    s << "## Pareto front\n\nNo other setting is both at least as fast and at least as accurate (RMSE). Plot: `"
      << in.plotFile << "`.\n\n" << kTableHead;
    std::vector<const SweepRow*> front;
    for (const SweepRow& r : rows)
        if (r.pareto) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->seconds < b->seconds; });
    for (const SweepRow* r : front) s << rowCells(*r);

    s << "\n## The sweep\n\n";
    s << sweepSentence(in.kind) << "\n\n";
    s << rows.size() << " renders; every row is in `" << in.csvFile << "`.\n\n" << kTableHead;
    for (const SweepRow& r : rows) s << rowCells(r);
    return s.str();
}

void writeSummary(const std::string& path, const SummaryInfo& info, const std::vector<SweepRow>& rows) {
    std::ofstream f(path);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f << summaryMarkdown(info, rows);
    if (!f.flush()) throw std::runtime_error(path + ": write failed");
}

}  // namespace rf::report
