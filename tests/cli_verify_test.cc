// `chromatag verify` as a user runs it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "test_util.h"

namespace chromatag {
namespace {

using testing::CommandResult;
using testing::CountLines;
using testing::ReadFile;
constexpr auto Chromatag = testing::RunChromatag;

TEST(CliVerifyTest, GeneratedSheetPassesAndATamperedSidecarFails) {
  const std::string sheet = ::testing::TempDir() + "/cli_verify.pdf";
  ASSERT_EQ(Chromatag({"generate", "--ids", "0-4", "--size", "30mm", "-o", sheet}).exit_code, 0);
  const auto ok = Chromatag({"verify", sheet});
  EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find("5 of 5 tags pass, nothing else found. PASS"), std::string::npos) << ok.out;

  const std::string sidecar = ::testing::TempDir() + "/cli_verify.pdf.json";
  auto json = nlohmann::json::parse(ReadFile(sidecar));
  json["tags"][2]["id"] = 9;
  std::ofstream(sidecar) << json.dump();
  const auto bad = Chromatag({"verify", "--json", sheet});
  EXPECT_EQ(bad.exit_code, 1);
  const auto report = nlohmann::json::parse(bad.out);
  EXPECT_FALSE(report["passed"].get<bool>());
  EXPECT_EQ(report["tags"][2]["found_id"], 2);
  EXPECT_NE(report["tags"][2]["problem"].get<std::string>().find("16h5 ID 9"), std::string::npos);
}

// A PDF and an SVG written one after the other into the same
// folder once shared tags.json, and verify of the PDF trusted the SVG's sidecar
// (PASS for IDs it did not hold). Each output now has its own sidecar, and a
// sidecar that describes another file is refused.
TEST(CliVerifyTest, EachOutputKeepsItsOwnSidecar) {
  const std::string dir = ::testing::TempDir() + "/cli_verify_own";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(Chromatag({"generate", "--ids", "0-3", "-o", dir + "/tags.pdf"}).exit_code, 0);
  ASSERT_EQ(Chromatag({"generate", "--ids", "6-9", "-o", dir + "/tags.svg"}).exit_code, 0);
  const auto pdf = Chromatag({"verify", "--json", dir + "/tags.pdf"});
  EXPECT_EQ(pdf.exit_code, 0) << pdf.err;
  const auto report = nlohmann::json::parse(pdf.out);
  ASSERT_EQ(report["tags"].size(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(report["tags"][i]["found_id"], i);

  // A sidecar copied beside another sheet (or an empty file) vouches for nothing.
  std::filesystem::copy_file(dir + "/tags.svg.json", dir + "/tags.pdf.json",
                             std::filesystem::copy_options::overwrite_existing);
  const auto swapped = Chromatag({"verify", dir + "/tags.pdf"});
  EXPECT_EQ(swapped.exit_code, 2);
  EXPECT_EQ(CountLines(swapped.err), 1) << swapped.err;
  EXPECT_NE(swapped.err.find("does not describe"), std::string::npos) << swapped.err;
  std::ofstream(dir + "/empty.pdf").close();
  std::filesystem::copy_file(dir + "/tags.svg.json", dir + "/empty.pdf.json");
  EXPECT_EQ(Chromatag({"verify", dir + "/empty.pdf"}).exit_code, 2);
}

TEST(CliVerifyTest, FamilyAuditRunsOnEveryKeptId) {
  const auto result = Chromatag({"verify", "--family", "16h5", "--all", "--json"});
  EXPECT_EQ(result.exit_code, 0) << result.err;
  const auto report = nlohmann::json::parse(result.out);
  EXPECT_EQ(report["tags"].size(), 28u);
  EXPECT_EQ(report["audit"]["min_distance"], 5);
  EXPECT_TRUE(report["audit"]["decoding_safe"].get<bool>());
  EXPECT_EQ(report["audit"]["bit_flips"][2]["wrong_id"], 0);
}

TEST(CliVerifyTest, StressReportsSizeTiltAndConditionsPerTag) {
  const std::string sheet = ::testing::TempDir() + "/cli_stress.pdf";
  ASSERT_EQ(Chromatag({"generate", "--ids", "0,1", "--size", "30mm", "-o", sheet}).exit_code, 0);
  const auto result = Chromatag({"verify", "--stress", "--json", sheet});
  const auto report = nlohmann::json::parse(result.out);
  ASSERT_EQ(report["stress"].size(), 2u);
  for (const auto& tag : report["stress"]) {
    EXPECT_GT(tag["smallest_size_px"].get<double>(), 5.0);
    EXPECT_LT(tag["smallest_size_px"].get<double>(), 60.0);
    EXPECT_GE(tag["largest_tilt_deg"].get<double>(), 40.0);
    EXPECT_EQ(tag["conditions"].size(), 6u);
    EXPECT_TRUE(tag["conditions"]["noise 8 levels"].get<bool>());
    EXPECT_TRUE(tag["conditions"]["Bayer"].get<bool>());
  }
}

TEST(CliVerifyTest, BadInputIsOneLineWithExitTwo) {
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"verify", "/nonexistent/tags.pdf"},
           {"verify"},
           {"verify", "--family", "16h5"},
           {"verify", "--family", "16h5", "--all", "--dpi", "5"},
           {"verify", "--family", "16h5", "--all", "--tolerance", "1ft"}}) {
    const auto result = Chromatag(args);
    EXPECT_EQ(result.exit_code, 2) << args.back();
    EXPECT_EQ(CountLines(result.err), 1) << result.err;
  }
}

}  // namespace
}  // namespace chromatag
