#include "farm/report/report_csv.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rf::report {

std::string formatNumber(double v, int digits) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (std::isnan(v)) return "nan";
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

namespace {
std::string num(double v) { return formatNumber(v, 6); }
}  // namespace

std::string csvHeader() {
    std::string s = "factor";
    for (const QualityKnob& k : qualityKnobs()) s += std::string(",") + k.column;
    return s +
           ",is_default,pareto,seconds,repeats,rays_primary,rays_shadow,rays_reflection,rays_refraction,"
           "rays_total,mrays_per_s,rmse,psnr_db,max_error,ssim";
}

std::string csvLine(const SweepRow& r) {
    const double mrays = r.seconds > 0 ? double(r.rays.total()) / r.seconds * 1e-6 : 0.0;
    // An external reference has no setting and no time: those cells stay empty.
    // Appended cell by cell (a long chain of string + trips GCC 12's -Wrestrict false positive).
    std::string s = r.factor;
    auto cell = [&s](const std::string& v) {
        s += ',';
        s += v;
    };
    for (double v : r.q.values) cell(r.external ? "" : num(v));
    cell(r.isDefault ? "1" : "0");
    cell(r.pareto ? "1" : "0");
    cell(r.external ? "" : num(r.seconds));
    cell(std::to_string(r.repeats));
    for (uint64_t c : {r.rays.primary, r.rays.shadow, r.rays.reflection, r.rays.refraction, r.rays.total()})
        cell(std::to_string(c));
    cell(r.external ? "" : num(mrays));
    for (double v : {r.error.rmse, r.error.psnr, r.error.maxError, r.error.ssim}) cell(num(v));
    return s;
}

void writeReportCsv(const std::string& path, const SweepRow& reference, const std::vector<SweepRow>& rows) {
    std::ofstream f(path);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f << csvHeader() << "\n" << csvLine(reference) << "\n";
    for (const SweepRow& r : rows) f << csvLine(r) << "\n";
    if (!f.flush()) throw std::runtime_error(path + ": write failed");
}

}  // namespace rf::report
