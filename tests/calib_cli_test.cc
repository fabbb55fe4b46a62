// `chromatag calib-sheet` and `chromatag calibrate` from the command line, on
// synthetic photos of the printed sheet: a good run whose outputs the other
// commands accept, and every kind of bad photo failing cleanly.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "calib_sim.h"
#include "chromatag/layout/calib_sheet_layout.h"
#include "test_util.h"

namespace chromatag {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::RunCommand;
using testing::SimCamera;
using testing::SimPrinter;

const std::string kCli = CHROMATAG_CLI_PATH;

std::string Read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CalibCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("chromatag-calib-cli-" + std::to_string(getpid()));
    fs::create_directories(dir_);
    const CommandResult r =
        RunCommand(kCli, {"calib-sheet", "-o", dir_ + "/calib.pdf", "--sheet-id", "4711"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string error;
    auto layout = ReadCalibSidecar(dir_ + "/calib.pdf.json", &error);
    ASSERT_TRUE(layout) << error;
    layout_ = new CalibSheetLayout(*layout);
  }
  static void TearDownTestSuite() {
    delete layout_;
    fs::remove_all(dir_);
  }

  // Writes a synthetic photo of `layout` (the test's sheet by default).
  static std::string Photo(const std::string& name, const SimCamera& camera,
                           const CalibSheetLayout* layout = nullptr,
                           const SimPrinter& printer = SimPrinter()) {
    const std::string path = dir_ + "/" + name;
    cv::imwrite(path, testing::RenderSheetPhoto(layout ? *layout : *layout_, printer, camera));
    return path;
  }

  // Runs calibrate into a fresh output folder; returns the result.
  static CommandResult Calibrate(const std::vector<std::string>& photos, const std::string& out) {
    std::vector<std::string> args = {"calibrate"};
    args.insert(args.end(), photos.begin(), photos.end());
    // The sheet as calib-sheet wrote it; its sidecar is read from beside it.
    args.insert(args.end(), {"--sheet", dir_ + "/calib.pdf", "-o", out});
    return RunCommand(kCli, args);
  }

  static std::string dir_;
  static CalibSheetLayout* layout_;
};

std::string CalibCliTest::dir_;
CalibSheetLayout* CalibCliTest::layout_ = nullptr;

TEST_F(CalibCliTest, SheetIsReproducibleAndNamesItsId) {
  EXPECT_EQ(layout_->sheet_id, 4711);
  const std::string first = Read(dir_ + "/calib.pdf");
  const CommandResult r =
      RunCommand(kCli, {"calib-sheet", "-o", dir_ + "/again.pdf", "--sheet-id", "4711"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("calibration sheet 4711"), std::string::npos) << r.out;
  EXPECT_EQ(Read(dir_ + "/again.pdf"), first);
}

TEST_F(CalibCliTest, SheetBadInputIsOneLineAndExitTwo) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"calib-sheet", "-o", dir_ + "/x.txt"},
        {"calib-sheet", "-o", dir_ + "/x.pdf", "--page", "80x80mm"},
        {"calib-sheet", "-o", dir_ + "/x.pdf", "--palette", "nope"},
        {"calib-sheet", "-o", dir_ + "/x.pdf", "--tag-size", "5mm"},
        // 0 was silently replaced by the derived ID.
        {"calib-sheet", "-o", dir_ + "/x.pdf", "--sheet-id", "0"},
        {"calib-sheet", "-o", dir_ + "/x.pdf", "--format", "png"}}) {
    const CommandResult r = RunCommand(kCli, args);
    EXPECT_EQ(r.exit_code, 2) << args.back();
    EXPECT_EQ(testing::CountLines(r.err), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir_ + "/x.pdf"));
  }
}

TEST_F(CalibCliTest, GoodPhotosGiveOutputsTheOtherCommandsAccept) {
  SimCamera warm;
  warm.gains = {1.1, 1.0, 0.85};
  SimCamera dim;
  dim.exposure = 0.6;
  dim.seed = 3;
  const std::string out = dir_ + "/out";
  const CommandResult r = Calibrate({Photo("warm.png", warm), Photo("dim.jpg", dim)}, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ADiffThresh"), std::string::npos) << r.out;
  // A warm and a neutral photo: no one white balance fits both, and the
  // summary and a warning say so.
  EXPECT_NE(r.out.find("White balance: none written, the photos disagree on the light"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.err.find("warning: no white balance: the photos disagree"), std::string::npos)
      << r.err;
  for (const char* name : {"detector.json", "palette.json", "printer.cube", "report.pdf",
                           "report.png", "measurements.json"})
    EXPECT_TRUE(fs::exists(out + "/" + name)) << name;
  EXPECT_EQ(Read(out + "/report.png").substr(1, 3), "PNG");
  const CommandResult palettes =
      RunCommand(kCli, {"palettes", "--palette-file", out + "/palette.json"});
  EXPECT_EQ(palettes.exit_code, 0) << palettes.err;
  const CommandResult generate = RunCommand(
      kCli,
      {"generate", "--ids", "0-3", "--color-lut", out + "/printer.cube", "-o", dir_ + "/tags.pdf"});
  EXPECT_EQ(generate.exit_code, 0) << generate.err;
  const CommandResult generate_palette =
      RunCommand(kCli, {"generate", "--ids", "0-3", "--palette-file", out + "/palette.json", "-o",
                        dir_ + "/tags2.pdf"});
  EXPECT_EQ(generate_palette.exit_code, 0) << generate_palette.err;
}

// The thresholds calibrate writes for a washed-out printer, loaded by
// `chromatag detect --config`, find a tag that the defaults miss.
TEST_F(CalibCliTest, DetectWithTheCalibratedConfigFindsWashedOutTags) {
  const SimPrinter washed_out = SimPrinter::WashedOut();
  SimCamera warm;
  warm.gains = {1.1, 1.0, 0.8};
  SimCamera neutral;
  neutral.exposure = 0.8;
  neutral.seed = 4;
  const std::string out = dir_ + "/out-washed";
  const CommandResult r = Calibrate(
      {Photo("w1.png", warm, nullptr, washed_out), Photo("w2.png", neutral, nullptr, washed_out)},
      out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  neutral.falloff = 0;
  const auto family = TagFamily::Load("16h5");
  const cv::Mat frame = testing::RenderPrintedTag(
      *family, 7, TagColors::FromPalette(layout_->palette), washed_out, neutral, 14, 320, 240);
  const std::string tag = dir_ + "/washed-tag.png";
  cv::imwrite(tag, frame);
  const CommandResult plain = RunCommand(kCli, {"detect", "--json", tag});
  EXPECT_EQ(plain.out.find("\"id\":7"), std::string::npos) << plain.out;
  const CommandResult tuned =
      RunCommand(kCli, {"detect", "--json", "--config", out + "/detector.json", tag});
  EXPECT_EQ(tuned.exit_code, 0) << tuned.err;
  EXPECT_NE(tuned.out.find("\"id\":7"), std::string::npos) << tuned.out;
  const CommandResult bad = RunCommand(kCli, {"detect", "--config", dir_ + "/calib.pdf.json", tag});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(testing::CountLines(bad.err), 1) << bad.err;
}

// Photos under one green cast: calibrate prints the white balance that
// undoes it and writes it into the config, which detect reads back.
TEST_F(CalibCliTest, OneLightGivesAWhiteBalanceThatDetectReads) {
  SimCamera near, far;
  near.gains = far.gains = {0.6, 1.0, 0.6};
  far.exposure = 0.7;
  far.seed = 5;
  const std::string out = dir_ + "/out-green";
  const CommandResult r = Calibrate({Photo("g1.png", near), Photo("g2.png", far)}, out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("White balance: R 1.000, G 0.6"), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("white balance"), std::string::npos) << r.err;
  const std::string config = Read(out + "/detector.json");
  EXPECT_NE(config.find("\"white_balance\": ["), std::string::npos) << config;
  const auto family = TagFamily::Load("16h5");
  const cv::Mat frame = testing::RenderPrintedTag(
      *family, 7, TagColors::FromPalette(layout_->palette), SimPrinter(), near, 14, 320, 240);
  const std::string tag = dir_ + "/green-tag.png";
  cv::imwrite(tag, frame);
  const CommandResult detect =
      RunCommand(kCli, {"detect", "--json", "--config", out + "/detector.json", tag});
  EXPECT_EQ(detect.exit_code, 0) << detect.err;
  EXPECT_NE(detect.out.find("\"id\":7"), std::string::npos) << detect.out;
}

// Each bad photo: exit 1, one line naming the photo and the problem, and no
// output folder (nothing written), even with a good photo beside it.
TEST_F(CalibCliTest, BadPhotosFailCleanly) {
  SimCamera good;
  const std::string good_photo = Photo("good.png", good);

  cv::imwrite(dir_ + "/empty.png", cv::Mat(900, 1200, CV_8UC3, cv::Scalar(120, 130, 125)));

  SimCamera partial;  // Only the top half of the sheet in the frame.
  partial.page_corners_px = {{{400, 100}, {1200, 100}, {1200, 1230}, {400, 1230}}};
  partial.height = 700;

  CalibSheetOptions other_options;
  other_options.palette = layout_->palette;
  other_options.sheet_id = 999;
  const auto other = LayoutCalibSheet(other_options);
  ASSERT_TRUE(other);

  SimCamera bright;
  bright.exposure = 1.6;
  SimCamera dark;
  dark.exposure = 0.035;
  dark.noise_sigma = 0.8;

  const struct {
    std::string photo;
    const char* says;
  } cases[] = {
      {dir_ + "/empty.png", "no ChromaTag found"},
      {Photo("partial.png", partial), "only 2 of the 4 corner tags of sheet 4711"},
      {Photo("other.png", good, &*other), "this is not sheet 4711"},
      {Photo("bright.png", bright), "overexposed"},
      {Photo("dark.png", dark), "underexposed"},
  };
  for (const auto& c : cases) {
    const std::string out = dir_ + "/bad-out";
    const CommandResult r = Calibrate({good_photo, c.photo}, out);
    EXPECT_EQ(r.exit_code, 1) << c.photo << ": " << r.err;
    EXPECT_EQ(testing::CountLines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.photo + ": "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.photo;
  }
  // Unreadable inputs are bad usage: exit 2.
  const CommandResult missing = Calibrate({dir_ + "/missing.jpg"}, dir_ + "/bad-out");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(testing::CountLines(missing.err), 1) << missing.err;
  // A sheet beside a sidecar that lists another file, and a sheet changed
  // since calib-sheet wrote it: the patches' colours would not be its own.
  fs::copy_file(dir_ + "/calib.pdf", dir_ + "/other.pdf");
  fs::copy_file(dir_ + "/calib.pdf.json", dir_ + "/other.pdf.json");
  const CommandResult wrong_sidecar = RunCommand(
      kCli, {"calibrate", good_photo, "--sheet", dir_ + "/other.pdf", "-o", dir_ + "/bad-out"});
  EXPECT_EQ(wrong_sidecar.exit_code, 2);
  EXPECT_NE(wrong_sidecar.err.find("does not describe"), std::string::npos) << wrong_sidecar.err;
  const std::string sheet = Read(dir_ + "/calib.pdf");
  std::ofstream(dir_ + "/changed.pdf", std::ios::binary) << sheet << "%";
  std::string sidecar = Read(dir_ + "/calib.pdf.json");
  sidecar.replace(sidecar.find("\"calib.pdf\""), 11, "\"changed.pdf\"");
  std::ofstream(dir_ + "/changed.pdf.json", std::ios::binary) << sidecar;
  const CommandResult changed = RunCommand(
      kCli, {"calibrate", good_photo, "--sheet", dir_ + "/changed.pdf", "-o", dir_ + "/bad-out"});
  EXPECT_EQ(changed.exit_code, 2);
  EXPECT_NE(changed.err.find("was changed after it was generated"), std::string::npos)
      << changed.err;
  EXPECT_FALSE(fs::exists(dir_ + "/bad-out"));
}

}  // namespace
}  // namespace chromatag
