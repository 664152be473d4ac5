#include "farm/cli/cli.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cerrno>

#include <unistd.h>

#include "engine/util/errors.h"
#include "farm/process/interrupt.h"
#include "engine/util/sample_count.h"

namespace rf::cli {

void printLine(const std::string& kind, const std::string& text) {
    // One line whatever the text holds: names from files and the command line are escaped.
    std::string line = "rayfarm: ";
    line += kind;
    line += ": ";
    line += printable(text);
    line += '\n';
    writeStderr(line);
}

void writeStderr(const std::string& line) { farm::writeStderrText(line); }

namespace {

/// Optimal string alignment distance: Levenshtein plus the swap of two neighbours ("--szie").
size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); ++i)
        for (size_t j = 1; j <= b.size(); ++j) {
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

}  // namespace

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
    // The dashes are not letters the user could have mistyped: "--sz" is 2 letters long.
    size_t letters = 0;
    for (char c : word) letters += c != '-';
    const size_t allowed = letters <= 3 ? 1 : 2;
    std::string best;
    size_t bestDistance = allowed + 1;
    for (const std::string& c : candidates) {
        const size_t d = editDistance(word, c);
        if (d < bestDistance) best = c, bestDistance = d;
    }
    return best;
}

void ArgParser::parse(const std::vector<std::string>& args) {
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.size() > 1 && a[0] == '-' && !(a.size() > 1 && (std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.'))) {
            std::string name = a, val;
            bool inlineVal = false;
            if (auto eq = a.find('='); eq != std::string::npos && a.rfind("--", 0) == 0) {
                name = a.substr(0, eq);
                val = a.substr(eq + 1);
                inlineVal = true;
            }
            auto it = takesValue_.find(name);
            if (it == takesValue_.end()) {
                const std::string near = closestMatch(name, declared());
                throw UsageError(command_ + ": unknown option " + name +
                                 (near.empty() ? "" : "; did you mean " + near + "?") + " (see rayfarm " + command_ + " --help)");
            }
            if (it->second) {
                if (!inlineVal) {
                    if (i + 1 >= args.size()) throw UsageError(name + ": expected a value");
                    val = args[++i];
                }
                values_[name] = val;
            } else {
                if (inlineVal) throw UsageError(name + ": takes no value");
                values_[name] = "";
            }
        } else {
            positional_.push_back(a);
        }
    }
}

std::optional<std::string> ArgParser::value(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return std::nullopt;
    return it->second;
}

int ArgParser::intValue(const std::string& name, int def, int lo, int hi) const {
    auto v = value(name);
    if (!v) return def;
    int out = 0;
    auto [p, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
    if (ec != std::errc() || p != v->data() + v->size() || out < lo || out > hi)
        throw UsageError(name + ": expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got \"" + *v + "\"");
    return out;
}

double ArgParser::doubleValue(const std::string& name, double def) const {
    auto v = value(name);
    if (!v) return def;
    try {
        size_t used = 0;
        const double d = std::stod(*v, &used);
        if (used != v->size() || !std::isfinite(d)) throw std::invalid_argument("");
        return d;
    } catch (const std::exception&) {
        throw UsageError(name + ": expected a number, got \"" + *v + "\"");
    }
}

bool ArgParser::sizeValue(const std::string& name, int& w, int& h) const {
    auto v = value(name);
    if (!v) return false;
    const auto x = v->find_first_of("xX");
    auto parse = [&](const std::string& s, int& out) {
        auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return ec == std::errc() && p == s.data() + s.size() && out >= 1 && out <= 16384;
    };
    if (x == std::string::npos || !parse(v->substr(0, x), w) || !parse(v->substr(x + 1), h))
        throw UsageError(name + ": expected WIDTHxHEIGHT (1 to 16384 each), got \"" + *v + "\"");
    return true;
}

void applyQualityOptions(const ArgParser& p, RenderSettings& s) {
    p.sizeValue("--size", s.width, s.height);
    s.spp = p.intValue("--spp", s.spp, 1, 4096);
    if (const std::string e = sppProblem(s.spp); !e.empty()) throw UsageError("--spp: " + e + ", got " + std::to_string(s.spp));
    s.maxDepth = p.intValue("--depth", s.maxDepth, 1, 64);
    const double w = p.doubleValue("--min-weight", s.minWeight);
    if (w < 0.0) throw UsageError("--min-weight: expected a number ≥ 0");
    s.minWeight = static_cast<float>(w);
    s.indirectSamples = p.intValue("--indirect", s.indirectSamples, 0, kMaxIndirectSamples);
    s.bounce = p.intValue("--bounce", s.bounce, 0, kMaxBounce);
    if (p.value("--bounce")) s.bounceMoving = true;  // asked for: moving geometry too
    if (auto t = p.value("--tonemap")) {
        if (*t == "clamp") s.toneMap = ToneMap::Clamp;
        else if (*t == "reinhard") s.toneMap = ToneMap::Reinhard;
        else if (*t == "pbr-neutral") s.toneMap = ToneMap::PbrNeutral;
        else throw UsageError("--tonemap: expected clamp, reinhard or pbr-neutral, got \"" + *t + "\"");
    }
    if (auto e = p.value("--exposure")) {
        s.autoExposure = *e == "auto";
        if (!s.autoExposure) {
            const double ev = p.doubleValue("--exposure", 0.0);
            if (std::abs(ev) > 64.0) throw UsageError("--exposure: expected auto or an EV from -64 to 64, got \"" + *e + "\"");
            s.exposure = float(ev);
        }
    }
}

void declareSceneOptions(ArgParser& p) {
    for (const char* o : {"--environment", "--environment-rotation", "--environment-intensity", "--ground", "--animation",
                          "--asset-root", "--max-texture-size", "--variant", "--camera", "--scene", "--point-size"})
        p.option(o);
}

SceneOptions sceneOptions(const ArgParser& p) {
    SceneOptions o;
    p.sizeValue("--size", o.width, o.height);  // an undeclared --size is simply absent
    if (auto f = p.value("--environment")) {
        if (f->empty()) throw UsageError("--environment: expected an .hdr or .exr file");
        o.environment = EnvironmentSpec{*f, 0.f, 1.f};
    }
    if (p.has("--environment-rotation")) o.environmentRotation = float(p.doubleValue("--environment-rotation", 0.0));
    if (p.has("--environment-intensity")) {
        const double k = p.doubleValue("--environment-intensity", 1.0);
        if (k < 0.0) throw UsageError("--environment-intensity: expected a number >= 0");
        o.environmentIntensity = float(k);
    }
    if (auto g = p.value("--ground")) {
        if (*g == "shadow") o.ground = Ground::Shadow;
        else if (*g == "none") o.ground = Ground::None;
        else throw UsageError("--ground: expected shadow or none, got \"" + *g + "\"");
    }
    if (auto a = p.value("--animation")) {
        if (a->empty()) throw UsageError("--animation: expected an animation's name or index");
        o.animation = *a;
    }
    if (p.has("--camera")) o.camera = p.intValue("--camera", 0, 0, 1 << 20);
    if (p.has("--scene")) {
        o.assets.scene = p.intValue("--scene", 0, 0, 1 << 20);
        o.assets.sceneSource = "--scene";
    }
    if (auto r = p.value("--asset-root")) {
        if (r->empty()) throw UsageError("--asset-root: expected a folder");
        o.assets.root = *r;
        o.rootFromCommandLine = true;
    }
    if (auto v = p.value("--variant")) {
        if (v->empty()) throw UsageError("--variant: expected a material variant's name");
        o.assets.variant = *v;
    }
    o.assets.maxTextureSize = p.intValue("--max-texture-size", o.assets.maxTextureSize, 16, 16384);
    if (auto v = p.value("--point-size")) {
        const double px = p.doubleValue("--point-size", o.assets.pointSize);
        if (!(px > 0.0 && px <= 100.0)) throw UsageError("--point-size: expected a width in pixels above 0 and up to 100, got \"" + *v + "\"");
        o.assets.pointSize = float(px);
    }
    return o;
}

}  // namespace rf::cli
