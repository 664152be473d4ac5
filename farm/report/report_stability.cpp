#include "farm/report/report_stability.h"

#include "farm/report/report_csv.h"
#include "farm/report/stability/stability_cases.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace rf::report {

namespace {

std::string num(double v) { return formatNumber(v, 4); }

std::string csvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c;
    }
    return q + "\"";
}

/// A table cell: a '|' in the text would split it.
std::string cell(const std::string& s) {
    std::string out;
    for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
}

std::string verdict(const StabilityCase& c) { return c.informative ? "info" : c.pass ? "pass" : "FAIL"; }

void writeFile(const std::string& path, const std::string& text) {
    std::ofstream f(path);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f << text;
    if (!f.flush()) throw std::runtime_error(path + ": write failed");
}

}  // namespace

int StabilityReport::passed() const {
    int n = 0;
    for (const StabilityCase& c : cases) n += !c.informative && c.pass;
    return n;
}

int StabilityReport::counted() const {
    int n = 0;
    for (const StabilityCase& c : cases) n += !c.informative;
    return n;
}

std::string stabilityMarkdown(const std::vector<StabilityCase>& cases) {
    int pass = 0, counted = 0;
    for (const StabilityCase& c : cases) {
        counted += !c.informative;
        pass += !c.informative && c.pass;
    }
    std::string s = "# Stiff and extreme cases\n\nCases of the stability catalogue (`docs/stability.md`, "
                    "numbered as there) that the engine's API can render or measure. " +
                    std::to_string(pass) + " of " + std::to_string(counted) +
                    " pass. Rows marked *info* show what a naive method does and are not counted.\n\n"
                    "| # | case | measured | error | tolerance | result |\n|---|---|---|---:|---:|---|\n";
    for (const StabilityCase& c : cases)
        s += "| " + c.id + " | " + cell(c.name) + " | " + cell(c.measured) + " | " + num(c.error) + " " + c.unit + " | " +
             (c.informative ? "–" : "≤ " + num(c.tolerance) + " " + c.unit) + " | " + verdict(c) + " |\n";
    return s;
}

std::string stabilityCsv(const std::vector<StabilityCase>& cases) {
    std::string s = "id,case,measured,error,tolerance,unit,result\n";
    for (const StabilityCase& c : cases)
        s += csvField(c.id) + "," + csvField(c.name) + "," + csvField(c.measured) + "," + num(c.error) + "," +
             num(c.tolerance) + "," + csvField(c.unit) + "," + verdict(c) + "\n";
    return s;
}

std::vector<StabilityCase> runStabilityCases(int threads) {
    std::vector<StabilityCase> out = stability::engineCases(threads);
    runTimelineCases(out);
    frameTimeCases(out);
    return out;
}

StabilityReport runStabilityReport(const std::string& outDir, int threads) {
    StabilityReport rep;
    rep.cases = runStabilityCases(threads);
    rep.markdownPath = (std::filesystem::path(outDir) / "stability.md").string();
    rep.csvPath = (std::filesystem::path(outDir) / "stability.csv").string();
    writeFile(rep.markdownPath, stabilityMarkdown(rep.cases));
    writeFile(rep.csvPath, stabilityCsv(rep.cases));
    return rep;
}

}  // namespace rf::report
