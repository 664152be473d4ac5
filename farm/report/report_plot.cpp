#include "farm/report/report_plot.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace rf::report {

namespace {

/// A log axis cannot show 0: an exact match is drawn at this floor (and said so in the key).
constexpr double kRmseFloor = 1e-6;

void point(std::ostream& s, const SweepRow& r) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.6g %.6g \"%s\"\n", r.seconds, std::max(r.error.rmse, kRmseFloor),
                  shortName(r.q).c_str());
    s << buf;
}

}  // namespace

std::string gnuplotQuote(const std::string& s) {
    std::string q = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') q += '\\';
        q += c;
    }
    return q + "\"";
}

std::string findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    std::istringstream in(dirs);
    std::string dir;
    while (std::getline(in, dir, ':')) {
        const std::string full = (dir.empty() ? "." : dir) + "/" + name;
        if (::access(full.c_str(), X_OK) == 0) return full;
    }
    return "";
}

namespace {

/// Log axes over the rows' time and error, with a second (PSNR) axis on the right.
void writeAxes(std::ostream& s, const std::vector<SweepRow>& rows) {
    // gnuplot cannot link a log axis to another, so the PSNR axis is a second log axis over the
    // same range, with tics placed where RMSE = 10^(−PSNR/20).
    double lo = 1e300, hi = 0.0, tlo = 1e300, thi = 0.0;
    for (const SweepRow& r : rows) {
        const double e = std::max(r.error.rmse, kRmseFloor);
        lo = std::min(lo, e);
        hi = std::max(hi, e);
        tlo = std::min(tlo, r.seconds);
        thi = std::max(thi, r.seconds);
    }
    if (rows.empty()) lo = hi = 0.1, tlo = thi = 1.0;
    lo /= 1.6, hi *= 1.6, tlo /= 1.6, thi *= 1.6;
    char range[160];
    std::snprintf(range, sizeof range, "set xrange [%.6g:%.6g]\nset yrange [%.6g:%.6g]\nset y2range [%.6g:%.6g]\n", tlo,
                  thi, lo, hi, lo, hi);
    s << range << "set logscale y2\nset y2label 'PSNR (dB)'\nset ytics nomirror\n";
    const int step = (-20.0 * std::log10(lo)) - (-20.0 * std::log10(hi)) > 40.0 ? 10 : 5;
    std::string tics;
    for (int db = 0; db <= 200; db += step) {
        const double e = std::pow(10.0, -db / 20.0);
        if (e < lo || e > hi) continue;
        char t[48];
        std::snprintf(t, sizeof t, "%s\"%d\" %.6g", tics.empty() ? "" : ", ", db, e);
        tics += t;
    }
    s << (tics.empty() ? std::string("unset y2tics\n") : "set y2tics (" + tics + ")\n");
    s << "set grid xtics ytics mxtics mytics lc rgb '#dddddd'\n";
    s << "set key outside right top box opaque noenhanced\n";
    s << "set format x '%g'\nset format y '%g'\n";
}

/// The data blocks (one per swept factor, the front, its labels, the default) and the plot
/// clauses that draw them.
std::vector<std::string> writeDataBlocks(std::ostream& s, const std::vector<SweepRow>& rows) {
    std::map<std::string, std::vector<const SweepRow*>> byFactor;
    std::vector<const SweepRow*> front;
    for (const SweepRow& r : rows) {
        byFactor[r.factor].push_back(&r);
        if (r.pareto) front.push_back(&r);
    }
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->seconds < b->seconds; });

    std::vector<std::string> plots;
    int style = 5;
    for (const auto& [factor, list] : byFactor) {
        const std::string block = "$f_" + factor;
        s << block << " << EOD\n";
        for (const SweepRow* r : list) point(s, *r);
        s << "EOD\n";
        plots.push_back(block + " using 1:2 with points pt " + std::to_string(style++) + " ps 1.3 title " +
                        gnuplotQuote("sweep: " + factor));
    }
    // Labels only where they do not pile up: a front point within 60% in both time and error of
    // the last labelled one keeps its mark but not its name.
    s << "$frontlabels << EOD\n";
    const SweepRow* lastLabel = nullptr;
    for (const SweepRow* r : front) {
        const auto near = [](double a, double b) { return std::abs(std::log(std::max(a, kRmseFloor) / std::max(b, kRmseFloor))) < std::log(1.6); };
        if (lastLabel && near(r->seconds, lastLabel->seconds) && near(r->error.rmse, lastLabel->error.rmse)) continue;
        point(s, *r);
        lastLabel = r;
    }
    s << "EOD\n$front << EOD\n";
    for (const SweepRow* r : front) point(s, *r);
    s << "EOD\n$default << EOD\n";
    for (const SweepRow& r : rows)
        if (r.isDefault) point(s, r);
    s << "EOD\n";
    plots.push_back("$front using 1:2 with linespoints lw 2 lc rgb '#d62728' pt 7 ps 0.8 title 'Pareto front'");
    plots.push_back("$frontlabels using 1:2:3 with labels offset 0.8,0.8 left font ',8' tc rgb '#d62728' notitle");
    plots.push_back("$default using 1:2 with points pt 6 ps 3.5 lw 2 lc rgb 'black' title 'default setting'");
    return plots;
}

}  // namespace

std::string gnuplotScript(const std::vector<SweepRow>& rows, const std::string& title, const std::string& pngPath) {
    std::ostringstream s;
    s << "# Error against run time, written by rayfarm report. Re-draw with: gnuplot THIS_FILE\n";
    s << "set terminal pngcairo size 960,640 enhanced font 'DejaVu Sans,10'\n";
    s << "set output " << gnuplotQuote(pngPath) << "\n";
    s << "set title " << gnuplotQuote(title) << " noenhanced\n";
    s << "set logscale xy\nset xlabel 'render time (s, fastest of repeats)'\n";
    s << "set ylabel 'RMSE against the reference (8-bit sRGB, 0..1)'\n";
    writeAxes(s, rows);
    const std::vector<std::string> plots = writeDataBlocks(s, rows);
    s << "plot ";
    for (size_t i = 0; i < plots.size(); ++i) s << (i ? ", \\\n     " : "") << plots[i];
    s << "\n";
    bool floored = false;
    for (const SweepRow& r : rows) floored |= r.error.rmse < kRmseFloor;
    if (floored) s << "# note: rows with RMSE below " << kRmseFloor << " are drawn at " << kRmseFloor << "\n";
    return s.str();
}

void runGnuplot(const std::string& script, const std::string& scriptPath, const std::string& pngPath) {
    const std::string gnuplot = findOnPath("gnuplot");
    if (gnuplot.empty()) throw std::runtime_error("gnuplot not found on PATH (Debian package gnuplot-nox)");
    {
        std::ofstream f(scriptPath);
        if (!f) throw std::runtime_error(scriptPath + ": cannot write");
        f << script;
        if (!f.flush()) throw std::runtime_error(scriptPath + ": write failed");
    }
    std::remove(pngPath.c_str());
    // posix_spawn with an argument vector: no shell, so paths need no quoting.
    std::vector<char*> argv{const_cast<char*>(gnuplot.c_str()), const_cast<char*>(scriptPath.c_str()), nullptr};
    pid_t pid = 0;
    if (posix_spawn(&pid, gnuplot.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
        throw std::runtime_error("cannot start " + gnuplot);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw std::runtime_error("waiting for gnuplot failed");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw std::runtime_error("gnuplot failed on " + scriptPath);
    std::ifstream png(pngPath, std::ios::binary);
    if (!png || png.peek() == std::ifstream::traits_type::eof())
        throw std::runtime_error("gnuplot wrote no plot to " + pngPath);
}

void plotErrorVsTime(const std::vector<SweepRow>& rows, const std::string& title, const std::string& scriptPath,
                     const std::string& pngPath) {
    runGnuplot(gnuplotScript(rows, title, pngPath), scriptPath, pngPath);
}

}  // namespace rf::report
