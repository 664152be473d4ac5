#pragma once
/// Typed reads out of parsed JSON for the scene file and its timeline: every error names the
/// file and the JSON path (`scene.json: lights[2].color: expected 3 numbers`).
#include <initializer_list>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "engine/util/vec_math.h"

namespace rf {

class JsonReader {
public:
    using json = nlohmann::json;

    /// file: named in every error. prefix: put before every JSON path (e.g. "timeline.").
    explicit JsonReader(std::string file, std::string prefix = "") : file_(std::move(file)), prefix_(std::move(prefix)) {}

    /// Throws InputError(file, "prefix+where: what"); with an empty where, the prefix alone
    /// names the place (or nothing does, without one).
    [[noreturn]] void fail(const std::string& where, const std::string& what) const;
    /// Fails on a key of object j that is not in keys (or when j is not an object).
    void allowKeys(const json& j, const std::string& where, std::initializer_list<const char*> keys) const;

    static std::string join(const std::string& where, const std::string& key) {
        return where.empty() ? key : where + "." + key;
    }
    static std::string index(const std::string& where, size_t i) { return where + "[" + std::to_string(i) + "]"; }

    /// A finite number.
    double number(const json& j, const std::string& where) const;
    /// obj[key] as a finite number, def when absent.
    double number(const json& obj, const char* key, const std::string& where, double def) const;
    double positive(const json& obj, const char* key, const std::string& where, double def) const;
    double nonNegative(const json& obj, const char* key, const std::string& where, double def) const;
    int integer(const json& obj, const char* key, const std::string& where, int def, int lo, int hi) const;
    bool boolean(const json& obj, const char* key, const std::string& where, bool def) const;
    std::string string(const json& obj, const char* key, const std::string& where, const std::string& def) const;
    /// Three finite numbers.
    DVec3 dvec3(const json& j, const std::string& where) const;
    DVec3 dvec3(const json& obj, const char* key, const std::string& where, const DVec3& def) const;
    /// Three numbers ≥ 0, or one grey number.
    Color color(const json& obj, const char* key, const std::string& where, const Color& def) const;
    /// v / |v|, failing on a zero or non-finite vector.
    DVec3 unit(const DVec3& v, const std::string& where) const;

    const std::string& file() const { return file_; }

private:
    std::string file_;
    std::string prefix_;
};

}  // namespace rf
