#include "json_guard.h"

#include <cmath>
#include <unordered_set>
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
    std::unordered_set<std::string> keys;
    std::string key;   ///< the object's current key
    size_t index = 0;  ///< the array's next element
};

/// Walks the text as SAX events, keeping only each open object's keys: linear in the text.
/// (nlohmann's callback parser, used before, rescans the parent object at every object's end
/// to drop discarded values, which made 40,000 materials take 30 s.)
class DuplicateKeyFinder : public nlohmann::json_sax<nlohmann::json> {
public:
    std::string found;

    bool null() override { return element(); }
    bool boolean(bool) override { return element(); }
    bool number_integer(number_integer_t) override { return element(); }
    bool number_unsigned(number_unsigned_t) override { return element(); }
    bool number_float(number_float_t, const string_t&) override { return element(); }
    bool string(string_t&) override { return element(); }
    bool binary(binary_t&) override { return element(); }
    bool start_object(std::size_t) override { return open(true); }
    bool start_array(std::size_t) override { return open(false); }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }
    bool key(string_t& k) override {
        Level& l = stack_.back();
        l.key = k;
        if (!l.keys.insert(k).second && found.empty()) {
            found = pathOf();
            if (!found.empty()) found += '.';
            found += k;
            return false;  // the first one is all we report: stop reading
        }
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

private:
    /// An array counts an element when it starts.
    bool element() {
        if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
        return true;
    }
    bool open(bool object) {
        element();
        stack_.push_back(Level{object, {}, {}, 0});
        return true;
    }
    bool close() {
        if (!stack_.empty()) stack_.pop_back();
        return true;
    }
    /// The path of the innermost open object (the one holding the current key).
    std::string pathOf() const {
        std::string p;
        for (size_t i = 0; i + 1 < stack_.size(); ++i) {
            const Level& l = stack_[i];
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

    std::vector<Level> stack_;
};

}  // namespace

std::string duplicateJsonKey(const std::string& text) {
    DuplicateKeyFinder finder;
    nlohmann::json::sax_parse(text, &finder);
    return finder.found;
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
