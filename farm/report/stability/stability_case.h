#pragma once
/// One measured case of the stability catalogue (docs/stability.md): what was set up, the
/// error measured and the tolerance it is held to.
#include <string>

namespace rf::stability {

/// One row of the stability table.
struct StabilityCase {
    std::string id;        ///< number in the catalogue ("21"), so a reader can look up the why
    std::string name;      ///< what was set up
    std::string measured;  ///< the figure, in words ("99.98% of pixels within 1/255")
    double error = 0.0;    ///< the measured error in the unit of tolerance
    double tolerance = 0.0;
    std::string unit;      ///< of error and tolerance
    bool pass = false;
    bool informative = false;  ///< shows what a naive method does: not counted as pass/fail
};

/// printf-style formatting of one number, for the `measured` texts.
std::string formatValue(const char* format, double v);

}  // namespace rf::stability
