#pragma once
/// The quality sweep of `rayfarm report`: which settings to render, timing each render, and its
/// error against a high-quality reference of the same frame.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/util/image.h"
#include "engine/util/image_metrics.h"
#include "farm/report/report_knobs.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_cache.h"
#include "engine/util/settings.h"
#include "engine/util/stats.h"

namespace rf::report {

/// One factor at a time around the base (cheap: about the cost of the spp line alone), or every
/// combination (the full grid: the product of the lists' lengths).
enum class SweepKind { OneFactor, FullGrid };

struct SweepSpec {
    /// The values to sweep, one list per knob in qualityKnobs() order (the table's defaults).
    std::vector<std::vector<double>> lists = defaultLists();
    /// The list of the knob called name ("spp", "depth", "min_weight", ...).
    std::vector<double>& list(const std::string& name) { return lists[knobIndex(name)]; }
    QualitySetting base;  ///< the default setting; always part of the sweep
    SweepKind kind = SweepKind::OneFactor;
    /// Timing: each setting is rendered again (round robin over all settings) until its renders
    /// add up to minTimingSeconds or it has maxRepeats; the fastest counts.
    double minTimingSeconds = 1.0;
    int maxRepeats = 9;

    /// Each knob's QualityKnob::sweep.
    static std::vector<std::vector<double>> defaultLists();
};

/// A setting to render and the sweep line it belongs to (a knob's name, "default" or "grid").
struct SweepPoint {
    QualitySetting q;
    std::string factor;
};

/// The settings to render, without duplicates (compared as RenderSettings holds them), the base
/// first.
std::vector<SweepPoint> makeSweep(const SweepSpec& spec);

/// A render with its time: the fastest of a few repeats, since other work on the machine only
/// ever adds time.
struct TimedRender {
    Image image;
    double seconds = 0.0;
    int repeats = 0;
    RayStats rays;  ///< of one render
};

/// Renders frame `frame` with settings; repeats while the total stays under minTotalSeconds
/// (at most maxRepeats times) and keeps the fastest time. bounceSlot: where the bounce cache is
/// kept (null: a slot for these repeats alone).
TimedRender renderTimed(const Scene& scene, const RenderSettings& settings, int frame, int threads,
                        double minTotalSeconds = 0.3, int maxRepeats = 5,
                        const std::shared_ptr<SceneCacheSlot>& bounceSlot = nullptr);

/// One row of the report.
struct SweepRow {
    QualitySetting q;
    std::string factor;  ///< sweep line, "reference" for the reference itself
    bool isDefault = false;
    bool external = false;  ///< the reference is an image from elsewhere: no setting, time or rays
    double seconds = 0.0;
    int repeats = 0;
    RayStats rays;
    ImageErrorMetrics error;
    bool pareto = false;  ///< no other row is at least as fast and at least as accurate
};

/// Renders every point, scores it against reference (8-bit sRGB, width × height of settings),
/// then re-times the points round robin (see SweepSpec). progress(i, n, row) after each first render.
/// bounceSlot: where the bounce cache is kept (null: one for this sweep).
std::vector<SweepRow> runSweep(const Scene& scene, const RenderSettings& settings, const SweepSpec& spec,
                               const std::vector<uint8_t>& reference, int frame, int threads,
                               const std::function<void(int, int, const SweepRow&)>& progress = {},
                               std::shared_ptr<SceneCacheSlot> bounceSlot = nullptr);

/// Sets SweepRow::pareto over (seconds, rmse): a row is on the front if no other row has
/// seconds ≤ and rmse ≤ with one of them strictly smaller.
void markPareto(std::vector<SweepRow>& rows);

}  // namespace rf::report
