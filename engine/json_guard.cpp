#include "json_guard.h"

#include <cmath>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "errors.h"

namespace rf {

std::string jsonDepthProblem(std::string_view text, int maxDepth) {
    int depth = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;  // the escaped character cannot end the string
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > maxDepth)
                return "JSON nests more than " + std::to_string(maxDepth) + " levels deep (at byte " + std::to_string(i) +
                       "); refused before parsing";
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
    return "";
}

namespace {

/// One open object or array while the parser walks the text, for naming a JSON path.
struct Level {
    bool object = false;
    std::set<std::string> keys;
    std::string key;   ///< the object's current key
    size_t index = 0;  ///< the array's next element
};

std::string pathOf(const std::vector<Level>& stack) {
    std::string p;
    for (size_t i = 0; i + 1 < stack.size(); ++i) {
        const Level& l = stack[i];
        if (l.object) {
            if (!p.empty()) p += '.';
            p += l.key;
        } else {
            p += '[';
            p += std::to_string(l.index - 1);
            p += ']';
        }
    }
    return p;
}

}  // namespace

std::string duplicateJsonKey(const std::string& text) {
    using json = nlohmann::json;
    std::vector<Level> stack;
    std::string found;
    // The callback sees every event; it drops every leaf value (returns false), so this pass
    // builds only empty containers. Arrays count an element when it starts.
    auto cb = [&](int, json::parse_event_t ev, json& parsed) -> bool {
        auto countElement = [&] {
            if (!stack.empty() && !stack.back().object) ++stack.back().index;
        };
        switch (ev) {
        case json::parse_event_t::object_start:
        case json::parse_event_t::array_start:
            countElement();
            stack.push_back(Level{ev == json::parse_event_t::object_start, {}, {}, 0});
            break;
        case json::parse_event_t::object_end:
        case json::parse_event_t::array_end:
            if (!stack.empty()) stack.pop_back();
            break;
        case json::parse_event_t::key: {
            Level& l = stack.back();
            l.key = parsed.get<std::string>();
            if (!l.keys.insert(l.key).second && found.empty()) {
                found = pathOf(stack);
                if (!found.empty()) found += '.';
                found += l.key;
            }
            break;
        }
        case json::parse_event_t::value:
            countElement();
            return false;
        }
        return true;
    };
    // Only the callback's findings matter (it keeps nothing, so the result is empty).
    const json ignored = json::parse(text, cb, false);
    (void)ignored;
    return found;
}

nlohmann::json parseUserJson(const std::string& file, const std::string& text) {
    if (std::string p = jsonDepthProblem(text); !p.empty()) throw InputError(file, p);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // parse errors, and numbers like 1e400 that overflow
        throw InputError(file, std::string("not valid JSON: ") + e.what());
    }
    if (std::string d = duplicateJsonKey(text); !d.empty())
        throw InputError(file, d + ": duplicate key (JSON keeps only one of them; remove the other)");
    return j;
}

std::string sceneNumberProblem(double v) {
    const double a = std::abs(v);
    if (a > kMaxSceneMagnitude) return "number beyond the range rayfarm renders (|x| ≤ 1e18)";
    if (a > 0.0 && a < 1.0 / kMaxSceneMagnitude) return "non-zero number too small for single precision (|x| ≥ 1e-18)";
    return "";
}

}  // namespace rf
