#pragma once
/// Checks on JSON text and numbers that every reader of user JSON shares: nesting depth (before
/// any recursive parser sees the text), duplicate keys (nlohmann keeps the last one silently)
/// and numbers the single-precision renderer cannot represent.
#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace rf {

/// Deepest nesting of objects and arrays the readers accept. tinygltf parses `extras`
/// recursively, so a few kilobytes of brackets would otherwise overflow the stack.
constexpr int kMaxJsonDepth = 128;

/// Largest magnitude a scene number may have: squares (|v|², r²) must stay inside float range.
constexpr double kMaxSceneMagnitude = 1e18;

/// Why `text` nests too deeply ("" if it does not). A linear scan that skips strings; it
/// does not validate the JSON.
std::string jsonDepthProblem(std::string_view text, int maxDepth = kMaxJsonDepth);

/// The JSON path of the first key that appears twice in one object ("" if none). `text` must
/// be valid JSON.
std::string duplicateJsonKey(const std::string& text);

/// Parses user JSON: refuses deep nesting, invalid JSON and duplicate keys, each with an
/// InputError naming `file`.
nlohmann::json parseUserJson(const std::string& file, const std::string& text);

/// Leaves `doc`'s contents allocated for the rest of the process, and doc null. For a load that
/// ran out of memory: nlohmann frees a document through a stack it allocates, and that
/// allocation failing inside its destructor ends the process (std::terminate) before the error
/// can be told. The process is about to exit with the error anyway.
void abandonJson(nlohmann::json& doc) noexcept;

/// Why a finite number read from a scene cannot be used in single precision ("" if it can):
/// beyond ±kMaxSceneMagnitude, or non-zero but so small it would round to zero.
std::string sceneNumberProblem(double v);

}  // namespace rf
