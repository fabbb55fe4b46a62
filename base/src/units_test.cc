#include "chromatag/base/units.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

TEST(UnitsTest, ParsesLengthsInEveryUnit) {
  EXPECT_DOUBLE_EQ(ParseLength("40mm")->mm, 40.0);
  EXPECT_DOUBLE_EQ(ParseLength("4 cm")->mm, 40.0);
  EXPECT_DOUBLE_EQ(ParseLength("0.04m")->mm, 40.0);
  EXPECT_DOUBLE_EQ(ParseLength("1.5IN")->mm, 38.1);
}

TEST(UnitsTest, RefusesBadLengthsAndSaysWhatIsAllowed) {
  std::string error;
  EXPECT_FALSE(ParseLength("40", &error));
  EXPECT_EQ(error, "invalid length '40': the unit is missing (units: mm, cm, m, in)");
  EXPECT_FALSE(ParseLength("40ft", &error));
  EXPECT_EQ(error, "invalid length '40ft': unknown unit 'ft' (units: mm, cm, m, in)");
  EXPECT_FALSE(ParseLength("0mm", &error));
  EXPECT_NE(error.find("greater than zero"), std::string::npos);
  EXPECT_FALSE(ParseLength("-3mm", &error));
  EXPECT_FALSE(ParseLength("mm", &error));
  EXPECT_FALSE(ParseLength("nanmm", &error));
  // Finite as typed, infinite in millimetres (found by fuzz_value_parsers).
  EXPECT_FALSE(ParseLength("1e308m", &error));
  EXPECT_EQ(error, "invalid length '1e308m': the length is too large");
  EXPECT_FALSE(ParseLength("0x1p1023in", &error));
}

TEST(UnitsTest, ParsesNamedAndCustomPages) {
  const auto a4 = ParsePageSize("A4");
  ASSERT_TRUE(a4);
  EXPECT_DOUBLE_EQ(a4->width_mm, 210.0);
  EXPECT_DOUBLE_EQ(a4->height_mm, 297.0);
  EXPECT_DOUBLE_EQ(ParsePageSize("letter")->width_mm, 215.9);
  const auto custom = ParsePageSize("8.5x11in");
  ASSERT_TRUE(custom);
  EXPECT_DOUBLE_EQ(custom->width_mm, 215.9);
  EXPECT_DOUBLE_EQ(custom->height_mm, 279.4);
  EXPECT_DOUBLE_EQ(ParsePageSize("10cmx150mm")->width_mm, 100.0);
  EXPECT_TRUE(a4->may_turn);
  // An orientation asked for: the page as named, never turned.
  for (const char* name : {"a4-landscape", "A4 Landscape"}) {
    const auto landscape = ParsePageSize(name);
    ASSERT_TRUE(landscape) << name;
    EXPECT_EQ(landscape->name, "a4 landscape");
    EXPECT_DOUBLE_EQ(landscape->width_mm, 297.0);
    EXPECT_DOUBLE_EQ(landscape->height_mm, 210.0);
    EXPECT_FALSE(landscape->may_turn);
  }
  const auto portrait = ParsePageSize("letter-portrait");
  ASSERT_TRUE(portrait);
  EXPECT_DOUBLE_EQ(portrait->width_mm, 215.9);
  EXPECT_FALSE(portrait->may_turn);
  std::string error;
  EXPECT_FALSE(ParsePageSize("a5", &error));
  EXPECT_NE(error.find("valid: a4, a3, letter, legal"), std::string::npos) << error;
  EXPECT_FALSE(ParsePageSize("100x", &error));
  EXPECT_FALSE(ParsePageSize("0x100mm", &error));
}

}  // namespace
}  // namespace chromatag
