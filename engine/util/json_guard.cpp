#include "engine/util/json_guard.h"

#include <cmath>
#include <new>
#include <unordered_set>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/util/errors.h"
#include "engine/util/load_control.h"

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

/// The duplicate-key rule over SAX events, keeping only each open object's keys: linear in the
/// text. (nlohmann's callback parser, used before, rescans the parent object at every object's
/// end to drop discarded values, which made 40,000 materials take 30 s.) Every few thousand
/// events it polls for a cancelled load: a 100 MB scene file is seconds of parsing.
class KeyRule {
public:
    std::string found;  ///< the first duplicate's path

    /// An array counts an element when it starts.
    void element() {
        if (++events_ % 4096 == 0) pollLoadCancel();
        if (!stack_.empty() && !stack_.back().object) ++stack_.back().index;
    }
    void open(bool object) {
        element();
        stack_.push_back(Level{object, {}, {}, 0});
    }
    void close() {
        if (!stack_.empty()) stack_.pop_back();
    }
    /// False at the first duplicate (then `found` names it).
    bool key(const std::string& k) {
        Level& l = stack_.back();
        l.key = k;
        if (l.keys.insert(k).second) return true;
        found = pathOf();
        if (!found.empty()) found += '.';
        found += k;
        return false;
    }

private:
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
    size_t events_ = 0;
};

/// SAX events through KeyRule only: finds the duplicate without building the document.
class DuplicateKeyFinder : public nlohmann::json_sax<nlohmann::json> {
public:
    KeyRule rule;

    bool null() override { return element(); }
    bool boolean(bool) override { return element(); }
    bool number_integer(number_integer_t) override { return element(); }
    bool number_unsigned(number_unsigned_t) override { return element(); }
    bool number_float(number_float_t, const string_t&) override { return element(); }
    bool string(string_t&) override { return element(); }
    bool binary(binary_t&) override { return element(); }
    bool start_object(std::size_t) override { return rule.open(true), true; }
    bool start_array(std::size_t) override { return rule.open(false), true; }
    bool end_object() override { return rule.close(), true; }
    bool end_array() override { return rule.close(), true; }
    bool key(string_t& k) override { return rule.key(k); }  // the first one is all we report: stop reading
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

private:
    bool element() { return rule.element(), true; }
};

/// The document built by nlohmann's own DOM builder and KeyRule in the same pass: one walk of
/// the text instead of two, and the parse polls for a cancelled load. (json_sax_dom_parser is
/// in nlohmann's detail namespace; Debian's 3.11.2 is what this is built against.)
class CheckedDomBuilder {
public:
    using json = nlohmann::json;
    using number_integer_t = json::number_integer_t;
    using number_unsigned_t = json::number_unsigned_t;
    using number_float_t = json::number_float_t;
    using string_t = json::string_t;
    using binary_t = json::binary_t;

    explicit CheckedDomBuilder(json& root) : dom_(root, true) {}
    KeyRule rule;

    bool null() { return rule.element(), dom_.null(); }
    bool boolean(bool v) { return rule.element(), dom_.boolean(v); }
    bool number_integer(number_integer_t v) { return rule.element(), dom_.number_integer(v); }
    bool number_unsigned(number_unsigned_t v) { return rule.element(), dom_.number_unsigned(v); }
    bool number_float(number_float_t v, const string_t& s) { return rule.element(), dom_.number_float(v, s); }
    bool string(string_t& v) { return rule.element(), dom_.string(v); }
    bool binary(binary_t& v) { return rule.element(), dom_.binary(v); }
    bool start_object(std::size_t n) { return rule.open(true), dom_.start_object(n); }
    bool start_array(std::size_t n) { return rule.open(false), dom_.start_array(n); }
    bool end_object() { return rule.close(), dom_.end_object(); }
    bool end_array() { return rule.close(), dom_.end_array(); }
    bool key(string_t& k) { return rule.key(k) && dom_.key(k); }
    template <class Exception>
    bool parse_error(std::size_t at, const std::string& token, const Exception& e) {
        return dom_.parse_error(at, token, e);  // throws e, as json::parse does
    }

private:
    nlohmann::detail::json_sax_dom_parser<json> dom_;
};

}  // namespace

std::string duplicateJsonKey(const std::string& text) {
    DuplicateKeyFinder finder;
    nlohmann::json::sax_parse(text, &finder);
    return finder.rule.found;
}

void abandonJson(nlohmann::json& doc) noexcept {
    // Moved (two words, no allocation) into storage that is never destroyed; a second call
    // reuses it, leaving the first document where it was.
    alignas(nlohmann::json) static unsigned char kept[sizeof(nlohmann::json)];
    new (kept) nlohmann::json(std::move(doc));
}

nlohmann::json parseUserJson(const std::string& file, const std::string& text) {
    LoadStep step("parsing its JSON");
    if (std::string p = jsonDepthProblem(text); !p.empty()) throw InputError(file, p);
    nlohmann::json j;
    CheckedDomBuilder builder(j);
    try {
        nlohmann::json::sax_parse(text, &builder);
    } catch (const nlohmann::json::exception& e) {  // parse errors, and numbers like 1e400 that overflow
        throw InputError(file, std::string("not valid JSON: ") + e.what());
    } catch (const std::bad_alloc&) {
        abandonJson(j);  // the part built so far
        throw;
    }
    if (!builder.rule.found.empty())
        throw InputError(file, builder.rule.found + ": duplicate key (JSON keeps only one of them; remove the other)");
    return j;
}

std::string sceneNumberProblem(double v) {
    const double a = std::abs(v);
    if (a > kMaxSceneMagnitude) return "number beyond the range rayfarm renders (|x| ≤ 1e18)";
    if (a > 0.0 && a < 1.0 / kMaxSceneMagnitude) return "non-zero number too small for single precision (|x| ≥ 1e-18)";
    return "";
}

}  // namespace rf
