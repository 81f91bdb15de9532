// The strict JSON reader every input goes through: bounded nesting, no duplicate keys, clear errors.
#include <gtest/gtest.h>

#include <string>

#include "json/strict.hpp"
#include "uavcover/error.hpp"

using uavcover::InputError;
using uavcover::strict::JsonLimits;
using uavcover::strict::parse_json;

namespace {

std::string nested_objects(std::size_t depth) {
  std::string s;
  for (std::size_t i = 0; i < depth; ++i) s += "{\"a\":";
  s += "1";
  s += std::string(depth, '}');
  return s;
}

std::string nested_arrays(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// The InputError thrown by parse_json(text, what), or a failure.
InputError error_of(const std::string& text, const std::string& what = "doc", const JsonLimits& limits = {}) {
  try {
    parse_json(text, what, limits);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << text.substr(0, 200);
  return InputError("", "");
}

}  // namespace

TEST(StrictJson, ParsesOrdinaryDocuments) {
  const auto j = parse_json(R"({"a": [1, 2.5, -3, true, null, "x"], "b": {"c": {}}, "d": []})", "doc");
  EXPECT_EQ(j["a"].size(), 6u);
  EXPECT_TRUE(j["a"][0].is_number_unsigned());
  EXPECT_TRUE(j["a"][2].is_number_integer());
  EXPECT_EQ(j["a"][1], 2.5);
  EXPECT_TRUE(j["b"]["c"].is_object());
  EXPECT_EQ(parse_json("42", "doc"), 42);
  EXPECT_EQ(parse_json("\"s\"", "doc"), "s");
}

TEST(StrictJson, NestingUpToTheLimitIsAccepted) {
  EXPECT_NO_THROW(parse_json(nested_objects(64), "doc"));
  EXPECT_NO_THROW(parse_json(nested_arrays(64), "doc"));
  const auto e = error_of(nested_arrays(65));
  EXPECT_EQ(e.field(), "doc");
  EXPECT_NE(std::string(e.what()).find("nested deeper than 64 levels"), std::string::npos) << e.what();
  JsonLimits shallow;
  shallow.max_depth = 3;
  EXPECT_NO_THROW(parse_json("[[[1]]]", "doc", shallow));
  EXPECT_THROW(parse_json("[[[[1]]]]", "doc", shallow), InputError);
}

TEST(StrictJson, DeepDocumentsAreRefusedWithoutRecursion) {
  // 70 000 nested objects (the size that overflowed the stack in `evaluate`) and 1 000 000 arrays
  const auto e = error_of(nested_objects(70'000), "paths");
  EXPECT_EQ(e.field(), "paths");
  EXPECT_NE(std::string(e.what()).find("nested deeper"), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("a.a.a"), std::string::npos) << "says where: " << e.what();
  EXPECT_THROW(parse_json(nested_arrays(1'000'000), "doc"), InputError);
  // unbalanced: deep but never closed
  EXPECT_THROW(parse_json(std::string(1'000'000, '['), "doc"), InputError);
}

TEST(StrictJson, DuplicateKeysAreRefusedByPath) {
  auto e = error_of(R"({"spacing_m": -5, "spacing_m": 40})", "mission");
  EXPECT_EQ(e.field(), "spacing_m");
  EXPECT_NE(std::string(e.what()).find("duplicate key \"spacing_m\" in mission"), std::string::npos)
      << e.what();
  e = error_of(R"({"uavs": [{"id": "a"}, {"id": "b", "share": 1, "id": "c"}]})", "mission");
  EXPECT_EQ(e.field(), "uavs[1].id") << e.what();
  e = error_of(R"({"a": {"b": [[], {"x": 1, "y": 2, "x": 3}]}})");
  EXPECT_EQ(e.field(), "a.b[1].x") << e.what();
  // the same key in different objects is fine
  EXPECT_NO_THROW(parse_json(R"({"a": {"k": 1}, "b": {"k": 2}, "k": [{"k": 3}, {"k": 4}]})", "doc"));
}

TEST(StrictJson, SyntaxErrorsAreInputErrorsNamingTheInput) {
  for (const char* bad : {"{\"a\": ", "{\"a\": 1,}", "[1 2]", "{\"a\": NaN}", "{\"a\": 1e999}", "// c\n{}",
                          "{'a': 1}", "\"\xff\"", "{} {}"}) {
    const auto e = error_of(bad, "plan.json");
    EXPECT_EQ(e.field(), "plan.json") << bad;
    EXPECT_NE(std::string(e.what()).find("malformed JSON"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
  }
}

TEST(StrictJson, EmptyAndOversizedTexts) {
  auto e = error_of("", "MISSION");
  EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  EXPECT_THROW(parse_json(" \n\t ", "doc"), InputError);
  JsonLimits small;
  small.max_bytes = 10;
  EXPECT_NO_THROW(parse_json("[1,2,3]", "doc", small));
  e = error_of("[1,2,3,4,5,6]", "body", small);
  EXPECT_EQ(e.field(), "body");
  EXPECT_NE(std::string(e.what()).find("more than the limit of 10 bytes"), std::string::npos) << e.what();
}

TEST(StrictJson, MessagesDoNotEchoControlCharacters) {
  const auto e = error_of("{\"a\\u001b[31m\": 1, \"a\\u001b[31m\": 2}");
  EXPECT_EQ(std::string(e.what()).find('\x1b'), std::string::npos) << e.what();
}
