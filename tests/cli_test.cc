// Runs the `chromatag` executable as a user would.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "chromatag/families/version.h"
#include "test_util.h"

namespace chromatag {
namespace {

using testing::CommandResult;
using testing::CountLines;
using testing::ReadFile;
constexpr auto Chromatag = testing::RunChromatag;

TEST(CliTest, HelpAndVersion) {
  const auto help = Chromatag({"--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("families"), std::string::npos);
  EXPECT_NE(help.out.find("palettes"), std::string::npos);
  const auto version = Chromatag({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out, std::string("chromatag ") + kVersion + "\n");
}

TEST(CliTest, NoSubcommandIsAUsageError) {
  const auto result = Chromatag({});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("error"), std::string::npos);
}

TEST(CliTest, FamiliesTableListsKeptAndRejectedIds) {
  const auto result = Chromatag({"families", "--family", "16h5"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("kept IDs       28 of 30: 0-4, 6-9, 11-29"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("5: red cells are all bit"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("10: red cells are all bit"), std::string::npos) << result.out;
  EXPECT_EQ(result.out.find("36h11"), std::string::npos);
}

TEST(CliTest, FamiliesJsonDescribesBothFamilies) {
  const auto result = Chromatag({"families", "--json"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  ASSERT_EQ(json["families"].size(), 2u);
  const auto& f16 = json["families"][0];
  EXPECT_EQ(f16["family"], "16h5");
  EXPECT_EQ(f16["kept_ids"].size(), 28u);
  EXPECT_EQ(f16["rejected_ids"][0]["id"], 5);
  EXPECT_EQ(f16["bits"], 16);
  EXPECT_EQ(f16["red_cells"], 4);
  EXPECT_EQ(f16["green_cells"], 12);
  EXPECT_LT(2 * f16["decoding_radius"].get<int>(), f16["min_hamming"].get<int>());
  const auto& f36 = json["families"][1];
  EXPECT_EQ(f36["family"], "36h11");
  EXPECT_EQ(f36["kept_ids"].size(), 587u);
  EXPECT_EQ(f36["red_cells"], 16);
}

TEST(CliTest, UnknownFamilyIsOneLineNamingTheValidOnes) {
  const auto result = Chromatag({"families", "--family", "25h9"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(result.out.empty());
  EXPECT_NE(result.err.find("16h5"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("36h11"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("25h9"), std::string::npos) << result.err;
  EXPECT_EQ(CountLines(result.err), 1) << result.err;
}

TEST(CliTest, PalettesShowsValuesAndChecks) {
  const auto result = Chromatag({"palettes", "--json"});
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  ASSERT_EQ(json["palettes"].size(), 2u);
  const auto& def = json["palettes"][0];
  EXPECT_EQ(def["name"], "default");
  EXPECT_EQ(def["shades"]["white"]["hex"], "#ffffff");
  EXPECT_EQ(def["shades"]["black"]["hex"], "#000000");
  for (const auto& check : def["checks"]) EXPECT_TRUE(check["passed"].get<bool>()) << check;
  const auto table = Chromatag({"palettes", "--palette", "iccv17"});
  ASSERT_EQ(table.exit_code, 0);
  EXPECT_NE(table.out.find("Palette iccv17"), std::string::npos);
  EXPECT_NE(table.out.find("warn"), std::string::npos);  // Its margins are small.
}

TEST(CliTest, UnknownPaletteIsOneLineNamingTheValidOnes) {
  const auto result = Chromatag({"palettes", "--palette", "neon"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(CountLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("valid: default, iccv17"), std::string::npos) << result.err;
}

TEST(CliTest, MalformedPaletteFileIsRefusedInOneLine) {
  const std::string path = ::testing::TempDir() + "/broken_palette.json";
  {
    std::ofstream file(path);
    file << R"({"lab": {"red-1": [50, 60, 0], "red-0": [50, 60, 40], "green-1": [50, -36, 4],
               "green-0": [54, -36, 50], "black": [0, 0, 0], "white": [100, 0, 0]}})";
  }
  const auto swapped = Chromatag({"palettes", "--palette-file", path});
  EXPECT_EQ(swapped.exit_code, 2);
  EXPECT_EQ(CountLines(swapped.err), 1) << swapped.err;
  EXPECT_NE(swapped.err.find("red-shades-b-order"), std::string::npos) << swapped.err;
  {
    std::ofstream file(path);
    file << "{ not json";
  }
  const auto garbage = Chromatag({"palettes", "--palette-file", path});
  EXPECT_EQ(garbage.exit_code, 2);
  EXPECT_EQ(CountLines(garbage.err), 1) << garbage.err;
  EXPECT_NE(garbage.err.find("not valid JSON"), std::string::npos) << garbage.err;
  std::remove(path.c_str());
  const auto missing = Chromatag({"palettes", "--palette-file", path});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("cannot read palette file"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace chromatag
