// Where a value of the scene text stands: JsonPositions follows a JSON pointer through the text
// without recursion, and the document parser reports duplicate keys, overflowing numbers and
// syntax errors at their line:column.
#include <string>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include "core/error.h"
#include "scene/json_document.h"
#include "scene/json_positions.h"

namespace rayes {
namespace {
using ::testing::HasSubstr;

TEST(JsonPositions, FollowsPointersThroughObjectsArraysAndEscapes) {
  const std::string text = "{\n  \"a\": [1, {\"b/c\": 2, \"d~e\": [3, 4]}],\n  \"q\\\"x\": \"}]\",\n  \"z\": 5\n}";
  const JsonPositions pos(text);
  EXPECT_EQ(pos.place(""), "1:1");
  EXPECT_EQ(pos.place("/a"), "2:8");
  EXPECT_EQ(pos.place("/a/0"), "2:9");
  EXPECT_EQ(pos.place("/a/1"), "2:12");
  EXPECT_EQ(pos.place("/a/1/b~1c"), "2:20");     // "/" in a key is ~1
  EXPECT_EQ(pos.place("/a/1/d~0e/1"), "2:34");   // "~" is ~0
  EXPECT_EQ(pos.place("/q\"x"), "3:11");         // an escaped quote in a key
  EXPECT_EQ(pos.place("/z"), "4:8");             // brackets inside a string are skipped
  EXPECT_EQ(pos.place("/a/7"), "2:8");           // missing: the deepest ancestor
  EXPECT_EQ(pos.place("/nope/0"), "1:1");
}

TEST(JsonPositions, DeepNestingCostsNoStack) {
  const int depth = 1'000'000;
  const std::string text = std::string(depth, '[') + std::string(depth, ']');
  std::string pointer;
  for (int k = 0; k < 3; ++k) pointer += "/0";
  EXPECT_EQ(JsonPositions(text).place(pointer), "1:4");
  EXPECT_EQ(JsonPositions("{\"a\": " + text + ", \"b\": 1}").place("/b"), "1:" + std::to_string(2 * depth + 14));
}

TEST(JsonPositions, KeysAreCountedInTextOrder) {
  const JsonPositions pos("{\"a\": {\"b\": \"c:\"},\n \"d\": 1}");
  EXPECT_EQ(pos.placeOfKey(0), "1:2");
  EXPECT_EQ(pos.placeOfKey(1), "1:8");
  EXPECT_EQ(pos.placeOfKey(2), "2:2");  // the string value "c:" is not a key
}

std::string parseError(const std::string& text) {
  try {
    parseJsonDocument(withoutByteOrderMark(text), "f.json");
  } catch (const InputError& e) {
    return e.message();
  }
  return "no error";
}

TEST(JsonDocument, DuplicateKeysOverflowAndSyntaxErrorsNameThePlace) {
  EXPECT_THAT(parseError("{\"a\": 1,\n \"a\": 2}"), HasSubstr("f.json:2:2: key 'a' appears twice"));
  EXPECT_THAT(parseError("{\"a\": {\"x\": 1}, \"b\": {\"x\": 1, \"x\": 1}}"), HasSubstr("f.json:1:31: key 'x'"));
  EXPECT_EQ(parseError("{\"a\": {\"x\": 1}, \"b\": {\"x\": 1}}"), "no error");  // same key, other objects
  EXPECT_THAT(parseError("{\"a\":\n  1e999}"), HasSubstr("f.json:2:7: JSON number overflow parsing '1e999'"));
  EXPECT_THAT(parseError("{\"a\": -1e400}"), HasSubstr("f.json:1:"));
  EXPECT_THAT(parseError("\xEF\xBB\xBF{\n  \"a\" 1}"), HasSubstr("f.json:2:7: JSON syntax error"));
  EXPECT_EQ(parseError("\xEF\xBB\xBF{}"), "no error");
}

}  // namespace
}  // namespace rayes
