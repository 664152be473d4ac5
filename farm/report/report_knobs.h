#pragma once
/// The quality knobs `rayfarm report` turns: one table, qualityKnobs(). The sweep, the CSV
/// columns, the plot labels, the summary's wording and the --sweep-NAME options all come from
/// it, so a new RenderSettings knob joins the report as one more line of that table.
#include <initializer_list>
#include <string>
#include <vector>

#include "engine/util/settings.h"

namespace rf::report {

/// What values a knob takes (checked when a --sweep-NAME list is parsed).
enum class KnobValues {
    Square,    ///< integers that are squares (samples per pixel)
    Integer,   ///< integers from lo to hi
    Fraction,  ///< numbers from lo to hi
};

/// One knob: where it lives in RenderSettings and what the report calls it.
struct QualityKnob {
    const char* name;       ///< sweep line and option stem: "spp" (--sweep-spp), "min_weight" (--sweep-min-weight)
    const char* column;     ///< CSV column: "max_depth"
    const char* describe;   ///< printf format of one value in a setting's name: "depth %g"
    const char* shortName;  ///< printf format of one value in the plot's labels: "d%g"
    const char* meaning;    ///< for the summary and --help: "maximum depth"
    KnobValues values;
    double lo, hi;
    std::vector<double> sweep;  ///< the default values to sweep
    double (*get)(const RenderSettings&);
    void (*set)(RenderSettings&, double);
};

/// Every knob, in the order of CSV columns and setting names.
const std::vector<QualityKnob>& qualityKnobs();
/// The index of the knob called name in qualityKnobs(); throws std::out_of_range if none is.
size_t knobIndex(const std::string& name);
/// "--sweep-" and the knob's name with '-' for '_'.
std::string sweepOption(const QualityKnob& k);

/// One value per knob, in qualityKnobs() order: one setting of the sweep.
struct QualitySetting {
    std::vector<double> values;
    /// Every knob at RenderSettings' default.
    QualitySetting();
    /// The first knobs in table order (spp, depth, min weight, ...), the rest at their default.
    QualitySetting(std::initializer_list<double> leading);
    /// The knob called name.
    double value(const std::string& name) const { return values[knobIndex(name)]; }
    void setValue(const std::string& name, double v) { values[knobIndex(name)] = v; }
    bool operator==(const QualitySetting&) const = default;
};

/// "spp 4, depth 5, min weight 0.001".
std::string describe(const QualitySetting& q);
/// "4spp d5 w0.001", for plot labels.
std::string shortName(const QualitySetting& q);

/// Settings with q applied over base.
RenderSettings withQuality(RenderSettings base, const QualitySetting& q);
/// The knobs' values in settings.
QualitySetting qualityOf(const RenderSettings& settings);
/// q as the settings hold it (0.001 becomes the float 0.001f), so equal settings compare equal.
QualitySetting normalized(const QualitySetting& q);

}  // namespace rf::report
