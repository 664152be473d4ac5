#pragma once
/// Command-line parsing shared by the subcommands (their entry points: farm/commands/commands.h
/// for render, still and info).
#include <map>
#include <optional>
#include <string>
#include <stdexcept>
#include <vector>

#include "engine/scene/scene_options.h"
#include "farm/process/usage_error.h"
#include "engine/util/settings.h"

namespace rf::cli {

/// Declares options first, then parses; unknown options are usage errors.
class ArgParser {
public:
    explicit ArgParser(std::string command) : command_(std::move(command)) {}
    void option(const std::string& name) { takesValue_[name] = true; }
    void flag(const std::string& name) { takesValue_[name] = false; }
    void parse(const std::vector<std::string>& args);

    bool has(const std::string& name) const { return values_.count(name) > 0; }
    std::optional<std::string> value(const std::string& name) const;
    const std::vector<std::string>& positional() const { return positional_; }
    /// Every option and flag declared, by name, in order of name.
    std::vector<std::string> declared() const {
        std::vector<std::string> out;
        for (const auto& [name, takesValue] : takesValue_) out.push_back(name);
        return out;
    }

    int intValue(const std::string& name, int def, int lo, int hi) const;
    double doubleValue(const std::string& name, double def) const;
    /// "WxH", both from 1 to 16384.
    bool sizeValue(const std::string& name, int& w, int& h) const;

private:
    std::string command_;
    std::map<std::string, bool> takesValue_;
    std::map<std::string, std::string> values_;
    std::vector<std::string> positional_;
};

/// The candidate closest to word by edit distance (insertions, deletions, substitutions and
/// swaps of two neighbours), when it is close enough to be a slip of the keyboard (at most 2
/// edits, fewer for short words); "" when none is.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

/// Applies --size, --spp, --depth, --min-weight and --tonemap to settings (declare them first).
void applyQualityOptions(const ArgParser& p, RenderSettings& s);

/// Writes "rayfarm: KIND: TEXT" and a newline to stderr in a single write(), so that under
/// mpirun, whose own lines share the terminal, the line never arrives in pieces.
void printLine(const std::string& kind, const std::string& text);
/// Writes text (whole lines) to stderr in a single write().
void writeStderr(const std::string& text);
/// Declares --environment FILE, --environment-rotation DEG, --environment-intensity K and
/// --ground shadow|none.
void declareSceneOptions(ArgParser& p);
/// Reads them (declare them first), and --size where the command has it; throws UsageError for
/// values that are not numbers.
SceneOptions sceneOptions(const ArgParser& p);

}  // namespace rf::cli
