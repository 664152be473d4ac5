#include "engine/util/json_reader.h"

#include <set>

#include <nlohmann/json.hpp>

#include "engine/util/errors.h"
#include "engine/util/json_guard.h"

namespace rf {

void JsonReader::fail(const std::string& where, const std::string& what) const {
    if (!where.empty()) throw InputError(file_, prefix_ + where + ": " + what);
    // The section itself: "timeline: expected an object" for the prefix "timeline.".
    std::string section = prefix_;
    if (!section.empty() && section.back() == '.') section.pop_back();
    throw InputError(file_, section.empty() ? what : section + ": " + what);
}

void JsonReader::allowKeys(const json& j, const std::string& where, std::initializer_list<const char*> keys) const {
    if (!j.is_object()) fail(where, "expected an object");
    const std::set<std::string> ok(keys.begin(), keys.end());
    for (auto it = j.begin(); it != j.end(); ++it)
        if (!ok.count(it.key())) fail(join(where, it.key()), "unknown key");
}

double JsonReader::number(const json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(where, "expected a finite number");
    if (std::string p = sceneNumberProblem(v); !p.empty()) fail(where, p);
    return v;
}

double JsonReader::number(const json& obj, const char* key, const std::string& where, double def) const {
    return obj.contains(key) ? number(obj[key], join(where, key)) : def;
}

double JsonReader::positive(const json& obj, const char* key, const std::string& where, double def) const {
    const double v = number(obj, key, where, def);
    if (!(v > 0.0)) fail(join(where, key), "expected a positive number");
    return v;
}

double JsonReader::nonNegative(const json& obj, const char* key, const std::string& where, double def) const {
    const double v = number(obj, key, where, def);
    if (v < 0.0) fail(join(where, key), "expected a number ≥ 0");
    return v;
}

int JsonReader::integer(const json& obj, const char* key, const std::string& where, int def, int lo, int hi) const {
    if (!obj.contains(key)) return def;
    const json& j = obj[key];
    if (!j.is_number_integer()) fail(join(where, key), "expected an integer");
    const long long v = j.get<long long>();
    if (v < lo || v > hi) fail(join(where, key), "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
    return static_cast<int>(v);
}

bool JsonReader::boolean(const json& obj, const char* key, const std::string& where, bool def) const {
    if (!obj.contains(key)) return def;
    if (!obj[key].is_boolean()) fail(join(where, key), "expected true or false");
    return obj[key].get<bool>();
}

std::string JsonReader::string(const json& obj, const char* key, const std::string& where, const std::string& def) const {
    if (!obj.contains(key)) return def;
    if (!obj[key].is_string()) fail(join(where, key), "expected a string");
    return obj[key].get<std::string>();
}

DVec3 JsonReader::dvec3(const json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 3) fail(where, "expected 3 numbers");
    return DVec3(number(j[0], where), number(j[1], where), number(j[2], where));
}

DVec3 JsonReader::dvec3(const json& obj, const char* key, const std::string& where, const DVec3& def) const {
    return obj.contains(key) ? dvec3(obj[key], join(where, key)) : def;
}

Color JsonReader::color(const json& obj, const char* key, const std::string& where, const Color& def) const {
    if (!obj.contains(key)) return def;
    const json& j = obj[key];
    if (j.is_number()) return Color(static_cast<float>(number(j, join(where, key))));
    const DVec3 c = dvec3(j, join(where, key));
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(join(where, key), "colour components must be ≥ 0");
    return Color(c);
}

DVec3 JsonReader::unit(const DVec3& v, const std::string& where) const {
    const double l = glm::length(v);
    if (!(l > 0.0) || !std::isfinite(l)) fail(where, "expected a non-zero direction");
    return v / l;
}

}  // namespace rf
