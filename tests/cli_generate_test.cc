// `chromatag generate` as a user runs it: outputs, and bad input refused in
// one line with exit code 2 and nothing written or damaged.
#include <dirent.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

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

// A fresh empty folder for one test.
std::string MakeDir(const std::string& name) {
  const std::string dir = ::testing::TempDir() + "/cli_generate_" + name;
  std::system(("rm -rf '" + dir + "'").c_str());
  mkdir(dir.c_str(), 0755);
  return dir;
}

std::vector<std::string> ListDir(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* entry = readdir(d)) {
      const std::string name = entry->d_name;
      if (name != "." && name != "..") names.push_back(name);
    }
    closedir(d);
  }
  return names;
}

TEST(CliGenerateTest, WritesPdfAndSidecarByteIdenticallyTwice) {
  const std::string dir = MakeDir("ok");
  const std::vector<std::string> args = {"generate", "--family", "16h5",           "--ids",
                                         "0-4",      "--size",   "40mm",           "--page",
                                         "a4",       "-o",       dir + "/tags.pdf"};
  const auto first = Chromatag(args);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find("Wrote 5 16h5 tags of 40 mm on 1 a4 page"), std::string::npos)
      << first.out;
  const std::string pdf = ReadFile(dir + "/tags.pdf");
  const std::string sidecar = ReadFile(dir + "/tags.pdf.json");
  ASSERT_EQ(pdf.rfind("%PDF-", 0), 0u);
  const auto json = nlohmann::json::parse(sidecar);
  EXPECT_EQ(json["schema"], "chromatag-layout");
  EXPECT_EQ(json["tags"].size(), 5u);
  EXPECT_EQ(json["files"][0]["path"], "tags.pdf");
  const auto second = Chromatag(args);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(ReadFile(dir + "/tags.pdf"), pdf);
  EXPECT_EQ(ReadFile(dir + "/tags.pdf.json"), sidecar);
}

// --format png -o x.pdf must not write a PNG named x.pdf.
TEST(CliGenerateTest, FormatThatDisagreesWithTheExtensionIsRefused) {
  const std::string dir = MakeDir("mismatch");
  const auto result =
      Chromatag({"generate", "--ids", "0", "--format", "png", "-o", dir + "/x.pdf"});
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(CountLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("the format is png but"), std::string::npos) << result.err;
  EXPECT_TRUE(ListDir(dir).empty());
  // Agreeing, or an extension that names no format, is fine.
  EXPECT_EQ(
      Chromatag({"generate", "--ids", "0", "--format", "pdf", "-o", dir + "/x.pdf"}).exit_code, 0);
  EXPECT_EQ(
      Chromatag({"generate", "--ids", "0", "--format", "svg", "-o", dir + "/x.drawing"}).exit_code,
      0);
}

TEST(CliGenerateTest, PngAndSvgFollowTheExtension) {
  const std::string dir = MakeDir("formats");
  auto png = Chromatag(
      {"generate", "--ids", "0", "--size", "1in", "--dpi", "100", "-o", dir + "/tag.png"});
  ASSERT_EQ(png.exit_code, 0) << png.err;
  EXPECT_EQ(ReadFile(dir + "/tag.png").substr(1, 3), "PNG");
  auto svg =
      Chromatag({"generate", "--all", "--size", "60mm", "--one-per-page", "-o", dir + "/tag.svg"});
  ASSERT_EQ(svg.exit_code, 0) << svg.err;
  EXPECT_NE(ReadFile(dir + "/tag-28.svg").find("<svg"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(ReadFile(dir + "/tag.svg.json"))["files"].size(), 28u);
}

struct BadCase {
  std::vector<std::string> args;
  std::string message;  // Part of the one line on stderr.
};

TEST(CliGenerateTest, BadInputIsOneLineExitTwoAndNothingWritten) {
  const std::string dir = MakeDir("bad");
  const std::string broken_lut = dir + "/broken.cube";
  std::ofstream(broken_lut) << "LUT_3D_SIZE 2\nnot a lut\n";
  const std::string out = dir + "/tags.pdf";
  const std::vector<BadCase> cases = {
      {{"--ids", "0", "--size", "300mm"}, "tag needs 500.0 x"},
      {{"--ids", "0", "--size", "0mm"}, "greater than zero"},
      {{"--ids", "0", "--size=-5mm"}, "greater than zero"},
      {{"--ids", "0", "--size", "40ft"}, "unknown unit 'ft' (units: mm, cm, m, in)"},
      {{"--ids", "0", "--size", "40"}, "the unit is missing"},
      {{"--ids", "5"},
       "16h5 ID 5 is rejected: red cells are all bit 1 (one shade, cannot be split)"},
      {{"--ids", "40"}, "outside 16h5 (IDs 0-29)"},
      {{"--ids", "0", "--color-lut", broken_lut}, "is not a LUT OpenColorIO can read"},
      {{"--ids", "0", "--color-lut", dir + "/missing.cube"}, "cannot read colour LUT"},
      {{"--ids", "0", "--palette", "neon"}, "valid: default, iccv17"},
      {{"--ids", "0", "--page", "a9"}, "valid: a4, a3, letter, legal"},
      {{"--ids", "0", "--family", "25h9"}, "not in {16h5,36h11}"},
      {{}, "say which tags: --ids 0-9,12 or --all"},
      // The libraries' messages with the flags named (cli/flag_terms.cc).
      {{"--ids", "0", "--palette", "neon"}, "or a palette file with --palette-file)"},
      {{"--board", "6y4"}, "--board must be COLSxROWS with 1 to 100 of each"},
      {{"--ids", "0", "--spacing", "5mm"},
       "--spacing is for boards (--board COLSxROWS); sheets take --gap"},
      {{"--board", "2x2", "--cut-ring"}, "no --one-per-page, --cut-ring or --crop-marks"},
      {{"--board", "6x4", "--quiet-zone", "20", "--spacing", "1mm"},
       "--spacing 1.0 mm holds the quiet zone of tags of at most 0.30 mm (20 cells of 6 across "
       "the black square); tags are 1 mm or more: give a larger --spacing or a smaller "
       "--quiet-zone"},
  };
  for (const auto& bad : cases) {
    std::vector<std::string> args = {"generate", "-o", out};
    args.insert(args.end(), bad.args.begin(), bad.args.end());
    const auto result = Chromatag(args);
    std::string joined;
    for (const auto& a : bad.args) joined += a + " ";
    EXPECT_EQ(result.exit_code, 2) << joined;
    EXPECT_EQ(CountLines(result.err), 1) << joined << ": " << result.err;
    EXPECT_NE(result.err.find(bad.message), std::string::npos) << joined << ": " << result.err;
    EXPECT_EQ(ListDir(dir).size(), 1u) << joined;  // Only broken.cube: no output, no temporary.
  }
}

TEST(CliGenerateTest, UnwritableOutputLeavesNothingAndExistingFilesIntact) {
  const auto unwritable = Chromatag({"generate", "--ids", "0", "-o", "/nonexistent/dir/tags.pdf"});
  EXPECT_EQ(unwritable.exit_code, 2);
  EXPECT_EQ(CountLines(unwritable.err), 1) << unwritable.err;
  EXPECT_NE(unwritable.err.find("cannot write '/nonexistent/dir/tags.pdf'"), std::string::npos)
      << unwritable.err;

  const std::string dir = MakeDir("keep");
  std::ofstream(dir + "/tags.pdf") << "an older sheet";
  std::ofstream(dir + "/tags.pdf.json") << "its sidecar";
  const auto too_big =
      Chromatag({"generate", "--ids", "0", "--size", "1m", "-o", dir + "/tags.pdf"});
  EXPECT_EQ(too_big.exit_code, 2);
  EXPECT_EQ(ReadFile(dir + "/tags.pdf"), "an older sheet");
  EXPECT_EQ(ReadFile(dir + "/tags.pdf.json"), "its sidecar");
  EXPECT_EQ(ListDir(dir).size(), 2u);
}

}  // namespace
}  // namespace chromatag
