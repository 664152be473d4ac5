// Shared checks on user JSON: nesting depth scanned before any recursive parser, duplicate keys
// named by their JSON path, and numbers a single-precision renderer cannot use.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/util/errors.h"
#include "engine/util/json_guard.h"

using namespace rf;

TEST(JsonGuard, DepthScanCountsBracketsOutsideStringsOnly) {
    EXPECT_EQ(jsonDepthProblem("{\"a\": [[[1]]]}", 4), "");
    EXPECT_NE(jsonDepthProblem("{\"a\": [[[[1]]]]}", 4), "");
    // Brackets inside strings (escaped quotes included) are text, not nesting.
    EXPECT_EQ(jsonDepthProblem(R"({"a": "[[[[[[\"[[[[[["})", 2), "");
    const std::string deep = std::string(20000, '[') + std::string(20000, ']');
    const std::string p = jsonDepthProblem(deep);
    EXPECT_NE(p.find("more than 128 levels"), std::string::npos) << p;
    EXPECT_NE(p.find("at byte 128"), std::string::npos) << p;
}

TEST(JsonGuard, DuplicateKeyIsNamedByItsPath) {
    EXPECT_EQ(duplicateJsonKey(R"({"a": 1, "b": {"a": 2}})"), "");
    EXPECT_EQ(duplicateJsonKey(R"({"a": 1, "a": 2})"), "a");
    EXPECT_EQ(duplicateJsonKey(R"({"objects": [{"r": 1}, {"x": [1, {"k": 0}], "r": 2, "r": 3}]})"), "objects[1].r");
    EXPECT_EQ(duplicateJsonKey(R"([[1, 2], {"m": {"c": 1, "c": 1}}])"), "[1].m.c");
}

// Issue 30 #3: the check is one pass (nlohmann's callback parser rescanned the parent object
// at every object's end: 40,000 materials took 30 s). 200,000 objects in one object, and
// 200,000 keys, the duplicate last: still found and named.
TEST(JsonGuard, DuplicateKeyAmongManyIsFoundInOnePass) {
    std::string objects = "{\"materials\": {", keys = "{\"extras\": {";
    for (int i = 0; i < 200000; ++i) {
        objects += "\"m" + std::to_string(i) + "\": {\"color\": [1, 1, 1]}, ";
        keys += "\"k" + std::to_string(i) + "\": " + std::to_string(i) + ", ";
    }
    EXPECT_EQ(duplicateJsonKey(objects + "\"last\": {}}}"), "");
    EXPECT_EQ(duplicateJsonKey(objects + "\"m123456\": {}}}"), "materials.m123456");
    EXPECT_EQ(duplicateJsonKey(keys + "\"k199999\": 0}}"), "extras.k199999");
    EXPECT_EQ(duplicateJsonKey(keys + "\"k\": {\"k0\": 1, \"k0\": 2}}}"), "extras.k.k0");
}

TEST(JsonGuard, ParseUserJsonRefusesEachProblemWithTheFile) {
    auto errorOf = [](const std::string& text) -> std::string {
        try {
            parseUserJson("f.json", text);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(errorOf(R"({"a": [1, 2]})"), "");
    EXPECT_NE(errorOf("{\"a\": ").find("f.json: not valid JSON"), std::string::npos);
    EXPECT_NE(errorOf(R"({"a": {"b": 1, "b": 2}})").find("f.json: a.b: duplicate key"), std::string::npos);
    EXPECT_NE(errorOf("{\"x\":" + std::string(500, '[') + std::string(500, ']') + "}").find("f.json: JSON nests"), std::string::npos);
}

TEST(JsonGuard, SceneNumbersMustFitSinglePrecisionSquares) {
    EXPECT_EQ(sceneNumberProblem(0.0), "");
    EXPECT_EQ(sceneNumberProblem(-1e7), "");
    EXPECT_EQ(sceneNumberProblem(1e18), "");
    EXPECT_NE(sceneNumberProblem(1e20), "");   // r² = 1e40 overflows a float
    EXPECT_NE(sceneNumberProblem(-1e39), "");  // beyond FLT_MAX itself
    EXPECT_NE(sceneNumberProblem(1e-40), "");  // would round to zero (or a denormal) in float
}
