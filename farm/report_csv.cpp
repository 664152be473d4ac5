#include "report_csv.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace rf::report {

namespace {
std::string num(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (std::isnan(v)) return "nan";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}
}  // namespace

std::string csvHeader() {
    return "factor,spp,max_depth,min_weight,is_default,pareto,seconds,repeats,rays_primary,rays_shadow,"
           "rays_reflection,rays_refraction,rays_total,mrays_per_s,rmse,psnr_db,max_error,ssim";
}

std::string csvLine(const SweepRow& r) {
    const double mrays = r.seconds > 0 ? double(r.rays.total()) / r.seconds * 1e-6 : 0.0;
    std::string s = r.factor + "," + std::to_string(r.q.spp) + "," + std::to_string(r.q.maxDepth) + "," +
                    num(r.q.minWeight) + "," + (r.isDefault ? "1" : "0") + "," + (r.pareto ? "1" : "0") + "," +
                    num(r.seconds) + "," + std::to_string(r.repeats);
    for (uint64_t c : {r.rays.primary, r.rays.shadow, r.rays.reflection, r.rays.refraction, r.rays.total()})
        s += "," + std::to_string(c);
    s += "," + num(mrays) + "," + num(r.error.rmse) + "," + num(r.error.psnr) + "," + num(r.error.maxError) + "," +
         num(r.error.ssim);
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
