#include "farm/report/report_sweep.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "engine/integrators/render.h"

namespace rf::report {

std::vector<std::vector<double>> SweepSpec::defaultLists() {
    std::vector<std::vector<double>> out;
    for (const QualityKnob& k : qualityKnobs()) out.push_back(k.sweep);
    return out;
}

namespace {

/// Every combination of the lists, the first knob varying slowest.
void addGrid(const SweepSpec& spec, size_t knob, QualitySetting& q,
             const std::function<void(const QualitySetting&, const std::string&)>& add) {
    if (knob == spec.lists.size()) return add(q, "grid");
    for (double v : spec.lists[knob]) {
        q.values[knob] = v;
        addGrid(spec, knob + 1, q, add);
    }
}

}  // namespace

std::vector<SweepPoint> makeSweep(const SweepSpec& spec) {
    std::vector<SweepPoint> out;
    auto add = [&](const QualitySetting& raw, const std::string& factor) {
        const QualitySetting q = normalized(raw);
        for (const SweepPoint& p : out)
            if (p.q == q) return;
        out.push_back({q, factor});
    };
    add(spec.base, "default");
    if (spec.kind == SweepKind::FullGrid) {
        QualitySetting q = spec.base;
        addGrid(spec, 0, q, add);
        return out;
    }
    const auto& knobs = qualityKnobs();
    for (size_t k = 0; k < knobs.size(); ++k)
        for (double v : spec.lists[k]) {
            QualitySetting q = spec.base;
            q.values[k] = v;
            add(q, knobs[k].name);
        }
    return out;
}

TimedRender renderTimed(const Scene& scene, const RenderSettings& settings, int frame, int threads,
                        double minTotalSeconds, int maxRepeats, const std::shared_ptr<SceneCacheSlot>& bounceSlot) {
    RenderView view{scene.camera, settings};
    if (bounceSlot) view.bounceSlot = bounceSlot;
    TimedRender r;
    double total = 0.0;
    r.seconds = 1e300;
    while (r.repeats < std::max(1, maxRepeats) && (r.repeats == 0 || total < minTotalSeconds)) {
        RayStats rays;
        const auto t0 = std::chrono::steady_clock::now();
        Image img = renderFrame(scene, view, frame, threads, rays);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        total += s;
        r.seconds = std::min(r.seconds, s);
        if (r.repeats == 0) {
            r.image = std::move(img);
            r.rays = rays;
        }
        ++r.repeats;
    }
    return r;
}

std::vector<SweepRow> runSweep(const Scene& scene, const RenderSettings& settings, const SweepSpec& spec,
                               const std::vector<uint8_t>& reference, int frame, int threads,
                               const std::function<void(int, int, const SweepRow&)>& progress,
                               std::shared_ptr<SceneCacheSlot> bounceSlot) {
    if (!bounceSlot) bounceSlot = std::make_shared<SceneCacheSlot>();
    const std::vector<SweepPoint> points = makeSweep(spec);
    std::vector<SweepRow> rows;
    std::vector<double> spent;
    rows.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        const RenderSettings s = withQuality(settings, points[i].q);
        const TimedRender r = renderTimed(scene, s, frame, threads, 0.0, 1, bounceSlot);
        SweepRow row;
        row.q = points[i].q;
        row.factor = points[i].factor;
        row.isDefault = points[i].q == normalized(spec.base);
        row.seconds = r.seconds;
        row.repeats = r.repeats;
        row.rays = r.rays;
        row.error = compareRgb8(toRgb8(r.image, s), reference, s.width, s.height);
        rows.push_back(row);
        spent.push_back(r.seconds);
        if (progress) progress(int(i) + 1, int(points.size()), rows.back());
    }
    // Repeats go round robin over the settings, not one setting at a time: a burst of other work
    // on the machine then slows one repeat of many settings instead of every repeat of one.
    for (int pass = 1; pass < spec.maxRepeats; ++pass) {
        bool any = false;
        for (size_t i = 0; i < rows.size(); ++i) {
            if (spent[i] >= spec.minTimingSeconds) continue;
            const TimedRender r =
                renderTimed(scene, withQuality(settings, rows[i].q), frame, threads, 0.0, 1, bounceSlot);
            spent[i] += r.seconds;
            rows[i].seconds = std::min(rows[i].seconds, r.seconds);
            ++rows[i].repeats;
            any = true;
        }
        if (!any) break;
    }
    markPareto(rows);
    return rows;
}

void markPareto(std::vector<SweepRow>& rows) {
    for (SweepRow& a : rows) {
        a.pareto = true;
        for (const SweepRow& b : rows) {
            if (&a == &b) continue;
            const bool noWorse = b.seconds <= a.seconds && b.error.rmse <= a.error.rmse;
            const bool better = b.seconds < a.seconds || b.error.rmse < a.error.rmse;
            if (noWorse && better) {
                a.pareto = false;
                break;
            }
        }
    }
}

}  // namespace rf::report
