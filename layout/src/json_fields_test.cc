#include "json_fields.h"

#include <gtest/gtest.h>

namespace chromatag::json_fields {
namespace {

std::string ErrorOf(void (*read)(const nlohmann::json&), const char* text) {
  try {
    read(nlohmann::json::parse(text));
  } catch (const FieldError& e) {
    return e.message;
  }
  return "";
}

// Numbers from a file are checked before any cast to int (a cast of 1e300 or
// 4294967300 is undefined, or silently wraps).
TEST(JsonFieldsTest, IntegersAreRangeCheckedBeforeTheCast) {
  auto read = [](const nlohmann::json& j) { Integer(j, "n", 1, 20); };
  EXPECT_EQ(ErrorOf(read, R"({"n": 1e300})"), "\"n\" must be an integer in [1, 20]");
  EXPECT_EQ(ErrorOf(read, R"({"n": 4294967300})"), "\"n\" must be an integer in [1, 20]");
  EXPECT_EQ(ErrorOf(read, R"({"n": 2.5})"), "\"n\" must be an integer in [1, 20]");
  EXPECT_EQ(ErrorOf(read, R"({"n": "2"})"), "\"n\" must be a number");
  EXPECT_EQ(ErrorOf(read, R"({"m": 2})"), "missing \"n\"");
  EXPECT_EQ(ErrorOf(read, R"([2])"), "missing \"n\"");
  EXPECT_EQ(ErrorOf(read, R"({"n": 20})"), "");
  EXPECT_EQ(Integer(nlohmann::json::parse(R"({"n": 7})"), "n", 1, 20), 7);
}

TEST(JsonFieldsTest, PointsAndStrings) {
  EXPECT_EQ(ErrorOf([](const nlohmann::json& j) { Point(j); }, "[1, 2, 3]"),
            "a position must be [x, y] in mm");
  EXPECT_EQ(ErrorOf([](const nlohmann::json& j) { String(j, "s"); }, R"({"s": 1})"),
            "\"s\" must be a string");
  const auto p = Point(nlohmann::json::parse("[1.5, -2]"));
  EXPECT_DOUBLE_EQ(p[0], 1.5);
  EXPECT_DOUBLE_EQ(p[1], -2.0);
}

}  // namespace
}  // namespace chromatag::json_fields
