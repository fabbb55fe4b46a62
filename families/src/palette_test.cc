#include "chromatag/families/palette.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace chromatag {
namespace {

Palette MustBuiltin(const std::string& name) {
  std::string error;
  auto palette = BuiltinPalette(name, &error);
  EXPECT_TRUE(palette) << error;
  return palette.value_or(Palette{});
}

const PaletteCheck* Find(const std::vector<PaletteCheck>& checks, const std::string& id) {
  for (const auto& check : checks) {
    if (check.id == id) return &check;
  }
  return nullptr;
}

TEST(PaletteTest, DefaultPaletteMeetsEveryConstraintOfSpecSection6) {
  const Palette palette = MustBuiltin("default");
  const auto checks = CheckPalette(palette);
  EXPECT_EQ(checks.size(), 14u);
  for (const auto& check : checks) {
    EXPECT_TRUE(check.passed) << check.id << ": " << check.description << ", got " << check.detail;
  }
  // And the spec's numbers themselves, independently of CheckPalette.
  const Lab r1 = palette[Shade::kRed1], r0 = palette[Shade::kRed0];
  const Lab g1 = palette[Shade::kGreen1], g0 = palette[Shade::kGreen0];
  for (Shade shade : kAllShades) EXPECT_TRUE(InSrgbGamut(palette[shade])) << ShadeName(shade);
  EXPECT_LE(std::fabs(r1.a - r0.a), 2.0);
  EXPECT_LE(std::fabs(g1.a - g0.a), 2.0);
  EXPECT_GE(std::min(r1.a, r0.a) - std::max(g1.a, g0.a), 80.0);
  EXPECT_GE(r1.b - r0.b, 35.0);
  EXPECT_GE(g0.b - g1.b, 35.0);
  EXPECT_LE(std::max({r1.L, r0.L, g1.L, g0.L}) - std::min({r1.L, r0.L, g1.L, g0.L}), 5.0);
  EXPECT_LT(g1.L, g0.L);  // green-1 is the darker green.
  EXPECT_LE(palette[Shade::kBlack].L, 10.0);
  EXPECT_GE(palette[Shade::kWhite].L, 95.0);
}

TEST(PaletteTest, Iccv17PaletteReproducesTheMeasuredRelations) {
  const Palette palette = MustBuiltin("iccv17");
  EXPECT_GT(palette[Shade::kRed1].b, palette[Shade::kRed0].b);
  EXPECT_GT(palette[Shade::kGreen0].b, palette[Shade::kGreen1].b);
  EXPECT_LT(palette[Shade::kGreen1].L, palette[Shade::kGreen0].L);
  const auto checks = CheckPalette(palette);
  EXPECT_TRUE(MeetsRequiredChecks(checks));
  // Its margins are the authors', well below the design rules.
  EXPECT_FALSE(Find(checks, "red-green-a-gap-design")->passed);
  EXPECT_FALSE(Find(checks, "red-b-gap-design")->passed);
}

TEST(PaletteTest, UnknownBuiltinNamesTheValidOnes) {
  std::string error;
  EXPECT_FALSE(BuiltinPalette("neon", &error));
  EXPECT_NE(error.find("valid: default, iccv17"), std::string::npos) << error;
}

TEST(PaletteTest, JsonRoundTrips) {
  const Palette palette = MustBuiltin("default");
  std::string error;
  auto parsed = ParsePalette(PaletteToJson(palette), "x", &error);
  ASSERT_TRUE(parsed) << error;
  EXPECT_EQ(parsed->name, "default");
  for (Shade shade : kAllShades) {
    EXPECT_NEAR((*parsed)[shade].L, palette[shade].L, 0.005);
    EXPECT_NEAR((*parsed)[shade].a, palette[shade].a, 0.005);
    EXPECT_NEAR((*parsed)[shade].b, palette[shade].b, 0.005);
  }
}

std::string PaletteJson(const std::string& red1, const std::string& red0 = "[50, 60, 0]") {
  return R"({"name": "test", "lab": {"red-1": )" + red1 + R"(, "red-0": )" + red0 +
         R"(, "green-1": [50, -36, 4], "green-0": [54, -36, 50],
             "black": [0, 0, 0], "white": [100, 0, 0]}})";
}

TEST(PaletteTest, RefusesFilesThatBreakARequiredConstraint) {
  std::string error;
  ASSERT_TRUE(ParsePalette(PaletteJson("[50, 60, 40]"), "x", &error)) << error;
  // Red shades swapped: red-1 must be the more orange (higher b*).
  EXPECT_FALSE(ParsePalette(PaletteJson("[50, 60, 0]", "[50, 60, 40]"), "x", &error));
  EXPECT_NE(error.find("red-shades-b-order"), std::string::npos) << error;
  EXPECT_NE(error.find("red-1 is the more orange red"), std::string::npos) << error;
  // A red that sRGB cannot show.
  EXPECT_FALSE(ParsePalette(PaletteJson("[50, 120, 40]"), "x", &error));
  EXPECT_NE(error.find("red-1 is outside sRGB"), std::string::npos) << error;
  // Red and green too close in a* for the detector to see the border.
  EXPECT_FALSE(ParsePalette(PaletteJson("[50, -30, 40]", "[50, -30, 0]"), "x", &error));
  EXPECT_NE(error.find("red-green-a-gap"), std::string::npos) << error;
}

TEST(PaletteTest, AcceptsButFlagsFilesThatOnlyMissTheDesignRules) {
  std::string error;
  auto palette = ParsePalette(PaletteJson("[50, 60, 20]"), "x", &error);
  ASSERT_TRUE(palette) << error;
  const auto checks = CheckPalette(*palette);
  EXPECT_FALSE(Find(checks, "red-b-gap-design")->passed);
  EXPECT_EQ(Find(checks, "red-b-gap-design")->detail, "20.0 - 0.0 = 20.0");
}

TEST(PaletteTest, RefusesMalformedFilesWithOneClearMessage) {
  std::string error;
  EXPECT_FALSE(ParsePalette("{\"lab\": ", "x", &error));
  EXPECT_EQ(error, "palette is not valid JSON");
  EXPECT_FALSE(ParsePalette(R"({"lab": {"red-1": [1, 2, 3]}})", "x", &error));
  EXPECT_NE(error.find("missing the shade \"red-0\""), std::string::npos) << error;
  EXPECT_FALSE(ParsePalette(R"({"lab": {"blue": [1, 2, 3]}})", "x", &error));
  EXPECT_NE(error.find("unknown shade \"blue\""), std::string::npos) << error;
  EXPECT_FALSE(ParsePalette(R"({"lab": {"red-1": [1, 2]}})", "x", &error));
  EXPECT_NE(error.find("three numbers"), std::string::npos) << error;
  EXPECT_FALSE(ParsePalette(R"({"lab": {"red-1": [150, 2, 3]}})", "x", &error));
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
  EXPECT_FALSE(ParsePalette(R"({"colours": {}})", "x", &error));
  EXPECT_NE(error.find("unknown member \"colours\""), std::string::npos) << error;
}

TEST(PaletteTest, LoadsFilesAndNamesUnreadableOnes) {
  std::string error;
  EXPECT_FALSE(LoadPaletteFile("/nonexistent/p.json", &error));
  EXPECT_EQ(error, "cannot read palette file '/nonexistent/p.json': no such file");
  const std::string path = testing::TempDir() + "/printer.json";
  {
    std::ofstream file(path);
    file << R"({"lab": {"red-1": [50, 60, 40], "red-0": [50, 60, 0], "green-1": [50, -36, 4],
               "green-0": [54, -36, 50], "black": [0, 0, 0], "white": [100, 0, 0]}})";
  }
  auto palette = LoadPaletteFile(path, &error);
  ASSERT_TRUE(palette) << error;
  EXPECT_EQ(palette->name, "printer");  // From the file name when it has none.
  std::remove(path.c_str());
}

}  // namespace
}  // namespace chromatag
