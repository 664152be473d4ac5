#include "farm/report/report_knobs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <type_traits>

namespace rf::report {

namespace {

/// A knob over the RenderSettings field Member (an arithmetic or enum field).
template <auto Member>
QualityKnob knob(const char* name, const char* column, const char* describe, const char* shortName, const char* meaning,
                 KnobValues values, double lo, double hi, std::vector<double> sweep) {
    auto get = [](const RenderSettings& s) { return static_cast<double>(s.*Member); };
    auto set = [](RenderSettings& s, double v) {
        using T = std::remove_reference_t<decltype(s.*Member)>;
        if constexpr (std::is_floating_point_v<T>)
            s.*Member = static_cast<T>(v);
        else
            s.*Member = static_cast<T>(std::lround(v));  // integers and enums
    };
    return {name, column, describe, shortName, meaning, values, lo, hi, std::move(sweep), get, set};
}

std::string format(const char* f, double v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

std::string joined(const QualitySetting& q, const char* QualityKnob::*fmt, const char* sep) {
    const auto& knobs = qualityKnobs();
    std::string s;
    for (size_t i = 0; i < knobs.size(); ++i) s += (i ? sep : "") + format(knobs[i].*fmt, q.values[i]);
    return s;
}

}  // namespace

const std::vector<QualityKnob>& qualityKnobs() {
    // One entry per knob: a knob added to RenderSettings joins the sweep, the CSV, the plot and
    // the CLI (--sweep-NAME) here.
    static const std::vector<QualityKnob> knobs = {
        knob<&RenderSettings::spp>("spp", "spp", "spp %g", "%gspp", "samples per pixel", KnobValues::Square, 1, 4096,
                                   {1, 4, 16, 64}),
        knob<&RenderSettings::maxDepth>("depth", "max_depth", "depth %g", "d%g", "maximum depth", KnobValues::Integer,
                                        1, 64, {1, 2, 3, 4, 5, 6, 7, 8}),
        knob<&RenderSettings::minWeight>("min_weight", "min_weight", "min weight %g", "w%g", "pruning weight",
                                         KnobValues::Fraction, 0, 1, {0, 1e-3, 1e-2, 0.1}),
        knob<&RenderSettings::indirectSamples>("indirect", "indirect_samples", "indirect %g", "i%g", "indirect samples",
                                               KnobValues::Integer, 0, kMaxIndirectSamples, {0, 1, 4, 16}),
        knob<&RenderSettings::bounce>("bounce", "bounce_kpoints", "bounce %g", "b%g", "bounce cache points (thousands)",
                                      KnobValues::Integer, 0, kMaxBounce, {0, 1, 4, 16}),
    };
    return knobs;
}

size_t knobIndex(const std::string& name) {
    const auto& knobs = qualityKnobs();
    for (size_t i = 0; i < knobs.size(); ++i)
        if (name == knobs[i].name) return i;
    throw std::out_of_range("report: no quality knob called " + name);
}

std::string sweepOption(const QualityKnob& k) {
    std::string s = std::string("--sweep-") + k.name;
    for (char& c : s)
        if (c == '_') c = '-';
    return s;
}

QualitySetting::QualitySetting() : QualitySetting(std::initializer_list<double>{}) {}

QualitySetting::QualitySetting(std::initializer_list<double> leading) {
    const RenderSettings defaults;
    for (const QualityKnob& k : qualityKnobs()) values.push_back(k.get(defaults));
    if (leading.size() > values.size()) throw std::invalid_argument("QualitySetting: more values than knobs");
    std::copy(leading.begin(), leading.end(), values.begin());
}

std::string describe(const QualitySetting& q) { return joined(q, &QualityKnob::describe, ", "); }

std::string shortName(const QualitySetting& q) { return joined(q, &QualityKnob::shortName, " "); }

RenderSettings withQuality(RenderSettings base, const QualitySetting& q) {
    const auto& knobs = qualityKnobs();
    for (size_t i = 0; i < knobs.size(); ++i) knobs[i].set(base, q.values[i]);
    return base;
}

QualitySetting qualityOf(const RenderSettings& settings) {
    QualitySetting q;
    const auto& knobs = qualityKnobs();
    for (size_t i = 0; i < knobs.size(); ++i) q.values[i] = knobs[i].get(settings);
    return q;
}

QualitySetting normalized(const QualitySetting& q) { return qualityOf(withQuality(RenderSettings{}, q)); }

}  // namespace rf::report
