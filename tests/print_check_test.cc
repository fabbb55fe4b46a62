// verify --print run as a command on simulated scans and photos of a sheet
// printed through a real press profile (icc_press.h): resolutions read from
// PNG, TIFF and JPEG, the report, JSON, and sidecars and input it refuses.
// The print check itself is tested beside it (verify/src/print_check_test.cc).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib_sim.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/verify/raster.h"
#include "icc_press.h"
#include "jpeg_segments.h"
#include "printed_sheet.h"
#include "test_util.h"

namespace chromatag {
namespace {

namespace fs = std::filesystem;
using testing::ExifApp1;
using testing::IccPress;
using testing::JpegWith;
using testing::PrintAndPhotograph;
using testing::PrintAndScan;
using testing::Resolution;
using testing::SimCamera;
using testing::SimScanner;

// The printed sheet (testing::MakePrintedSheet), made once for the suite.
class PrintCheckCliTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    sheet_ = testing::MakePrintedSheet("chromatag-print-check-cli", &error).release();
    ASSERT_NE(sheet_, nullptr) << error;
    dir_ = &sheet_->dir;
    record_ = &sheet_->record;
    images_ = &sheet_->images;
    press_ = sheet_->press.get();
  }
  static void TearDownTestSuite() { delete sheet_; }

  static double PxPerMm() { return testing::PrintedSheet::PxPerMm(); }

  static inline testing::PrintedSheet* sheet_ = nullptr;
  static inline const std::string* dir_ = nullptr;
  static inline SheetRecord* record_ = nullptr;
  static inline SheetImages* images_ = nullptr;
  static inline IccPress* press_ = nullptr;
};

// A photo tilted about one axis: the library's verdict (verify's
// print_check_test) is PASS with warnings, and the command says so.
TEST_F(PrintCheckCliTest, TiltedPhotoPassesSayingTheShapeWasNotChecked) {
  SimCamera camera;
  camera.width = 2400;
  camera.height = 1800;
  camera.page_corners_px =
      testing::PinholePageCorners(record_->page, 1800, 30, 0, 420, {camera.width, camera.height});
  const cv::Mat photo =
      PrintAndPhotograph(images_->pages[1], PxPerMm(), press_->AsPrintFn(), {1.0, 1.04}, camera);
  const std::string file = *dir_ + "/tilted.png";
  ASSERT_TRUE(cv::imwrite(file, photo));
  const auto run = testing::RunChromatag({"verify", *dir_ + "/tags.pdf", "--print", file});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("pass; the page's shape was not checked. PASS with warnings"),
            std::string::npos)
      << run.out;
  // In the command line's terms (cli/flag_terms.cc).
  EXPECT_NE(run.out.find("give --camera, add a photo"), std::string::npos) << run.out;
}

TEST_F(PrintCheckCliTest, ChecksScansAndReportsAndRefusesBadInput) {
  using testing::RunChromatag;
  const std::string sheet = *dir_ + "/tags.pdf";
  const std::string good = *dir_ + "/good.png", small = *dir_ + "/small.png";
  SimScanner scanner;
  ASSERT_TRUE(cv::imwrite(
      good, PrintAndScan(images_->pages[0], PxPerMm(), press_->AsPrintFn(), {}, scanner)));
  ASSERT_TRUE(cv::imwrite(small, PrintAndScan(images_->pages[1], PxPerMm(), press_->AsPrintFn(),
                                              {0.97, 0.97}, scanner)));
  // OpenCV writes no resolution into the PNG: --scan alone is refused.
  auto r = RunChromatag({"verify", sheet, "--print", good, "--scan"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("does not record its resolution; give it with --scan-dpi"),
            std::string::npos)
      << r.err;
  // A TIFF records its resolution (as scanners write it).
  const std::string tiff = *dir_ + "/good.tif";
  ASSERT_TRUE(cv::imwrite(
      tiff, cv::imread(good),
      {cv::IMWRITE_TIFF_RESUNIT, 2, cv::IMWRITE_TIFF_XDPI, 300, cv::IMWRITE_TIFF_YDPI, 300}));
  r = RunChromatag({"verify", sheet, "--print", tiff, "--scan"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("scan at 300 dpi, 12 of 12 tags found"), std::string::npos) << r.out;
  // So does a JPEG in its EXIF alone (as cameras and most scanners write it).
  const std::string jpeg = *dir_ + "/good.jpg";
  std::ofstream(jpeg, std::ios::binary)
      << JpegWith(cv::imread(good), "", ExifApp1({Resolution(300, 1, 300, 1, 2)}));
  r = RunChromatag({"verify", sheet, "--print", jpeg, "--scan"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("scan at 300 dpi, 12 of 12 tags found"), std::string::npos) << r.out;
  const std::string report = *dir_ + "/report.pdf";
  r = RunChromatag({"verify", sheet, "--print", good, "--scan-dpi", "300", "--report", report});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("page 1 of 3, scan at 300 dpi, 12 of 12 tags found"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("page 2: no scan or photo shows it (not checked)"), std::string::npos);
  EXPECT_EQ(testing::ReadFile(report).rfind("%PDF", 0), 0u);
  // The shrunk page fails, in JSON too, naming the scale; the sidecar may be
  // given instead of the sheet.
  r = RunChromatag({"verify", "--sheet", sheet + ".json", "--print", good, small, "--scan-dpi",
                    "300", "--json"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_EQ(json["grade"], "fail");
  ASSERT_EQ(json["images"].size(), 2u);
  EXPECT_EQ(json["images"][0]["grade"], "pass");
  EXPECT_EQ(json["images"][1]["page"], 2);
  EXPECT_NEAR(json["images"][1]["scale"]["x"].get<double>(), 0.97, 0.002);
  EXPECT_NE(json["images"][1]["problems"][0].get<std::string>().find("printed at 97.0 %"),
            std::string::npos);
  // A PNG sheet records its resolution: as a "scan" of itself it passes,
  // read through --scan alone. One written at 30 dpi is refused.
  const std::string png_sheet = *dir_ + "/sheet.png", low = *dir_ + "/low.png";
  ASSERT_EQ(RunChromatag({"generate", "--family", "16h5", "--ids", "0-3", "--size", "30mm",
                          "--format", "png", "--dpi", "300", "-o", png_sheet})
                .exit_code,
            0);
  r = RunChromatag({"verify", png_sheet, "--print", png_sheet, "--scan"});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("scan at 300 dpi, 4 of 4 tags found; scale x 1.000"), std::string::npos)
      << r.out;
  ASSERT_EQ(RunChromatag({"generate", "--family", "16h5", "--ids", "0-3", "--size", "30mm",
                          "--format", "png", "--dpi", "30", "-o", low})
                .exit_code,
            0);
  r = RunChromatag({"verify", png_sheet, "--print", low, "--scan"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("records 30 x 30 dpi, outside [50, 4800]"), std::string::npos) << r.err;
  // A sidecar copied beside another sheet vouches for nothing.
  fs::copy_file(sheet, *dir_ + "/other.pdf", fs::copy_options::overwrite_existing);
  fs::copy_file(sheet + ".json", *dir_ + "/other.pdf.json", fs::copy_options::overwrite_existing);
  r = RunChromatag({"verify", *dir_ + "/other.pdf", "--print", good, "--scan-dpi", "300"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("does not describe"), std::string::npos) << r.err;
  // A sidecar edited after the sheet was written: cut down to one tag of the
  // scanned page (the other tags found there are on the page, where it has
  // none: FAIL), claiming 100,000 pages (refused: the PDF has fewer), or
  // beside a sheet changed since (refused: its SHA-256 differs).
  {
    auto sidecar = nlohmann::json::parse(testing::ReadFile(sheet + ".json"));
    nlohmann::json kept = nlohmann::json::array();
    bool first = true;
    for (const auto& tag : sidecar["tags"]) {
      if (tag["page"] != 1 || first) kept.push_back(tag);
      if (tag["page"] == 1) first = false;
    }
    sidecar["tags"] = kept;
    std::ofstream(*dir_ + "/cut.json") << sidecar.dump(2);
    sidecar["page"]["count"] = 100000;
    std::ofstream(*dir_ + "/pages.json") << sidecar.dump(2);
  }
  r = RunChromatag({"verify", *dir_ + "/cut.json", "--print", good, "--scan-dpi", "300"});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("where the sidecar has no tag: the sidecar does not describe this print"),
            std::string::npos)
      << r.out;
  r = RunChromatag({"verify", *dir_ + "/pages.json", "--print", good, "--scan-dpi", "300"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(testing::CountLines(r.err), 1) << r.err;
  {
    std::ofstream(*dir_ + "/changed.pdf", std::ios::binary)
        << testing::ReadFile(sheet) << "% changed\n";
    std::string text = testing::ReadFile(sheet + ".json");
    text.replace(text.find("\"tags.pdf\""), 10, "\"changed.pdf\"");
    std::ofstream(*dir_ + "/changed.pdf.json") << text;
  }
  r = RunChromatag({"verify", *dir_ + "/changed.pdf", "--print", good, "--scan-dpi", "300"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("does not match '" + *dir_ + "/changed.pdf': the sheet's SHA-256 differs"),
            std::string::npos)
      << r.err;
  // A sidecar whose tag size no check can work with.
  {
    std::string text = testing::ReadFile(sheet + ".json");
    const std::string field = "\"tag_size_mm\": 30.0";
    ASSERT_NE(text.find(field), std::string::npos);
    text.replace(text.find(field), field.size(), "\"tag_size_mm\": 1e9");
    std::ofstream(*dir_ + "/huge-tag.json") << text;
  }
  r = RunChromatag({"verify", *dir_ + "/huge-tag.json", "--print", good, "--scan-dpi", "300"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(testing::CountLines(r.err), 1) << r.err;
  // Bad input: one line, exit 2. A PNG whose header claims 40000 x 40000
  // pixels is refused before decoding.
  const std::string huge = *dir_ + "/huge.png";
  {
    std::string header("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\x9c\x40\0\0\x9c\x40\x08\x02\0\0\0", 29);
    std::ofstream(huge, std::ios::binary) << header << std::string(64, '\0');
  }
  r = RunChromatag({"verify", sheet, "--print", huge, "--scan-dpi", "300"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("40000 x 40000 pixels, over the limit of 256 Mpx"), std::string::npos)
      << r.err;
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"verify", sheet, "--print", *dir_ + "/nothere.png"},
           {"verify", sheet, "--print", sheet},
           {"verify", "--print", good},
           {"verify", sheet, "--print", good, "--report", *dir_ + "/r.txt"},
           {"verify", sheet, "--print", good, "--scan-dpi", "5"},
           {"verify", sheet, "--print", good, "--scan-dpi", "0"},
           {"verify", sheet, "--print", good, "--scan-dpi", "-300"},
           {"verify", sheet, "--print", good, "--scale-tolerance", "half"},
           {"verify", sheet, "--print", good, "--stress"},
           {"verify", sheet, "--scan"}}) {
    r = RunChromatag(args);
    EXPECT_EQ(r.exit_code, 2) << args.back() << ": " << r.err;
    EXPECT_EQ(testing::CountLines(r.err), 1) << r.err;
  }
}

}  // namespace
}  // namespace chromatag
