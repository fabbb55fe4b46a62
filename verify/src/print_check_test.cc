// CheckPrintImage on simulated scans and photos of sheets printed through a
// real press profile (icc_press.h): a good print passes; a print shrunk by
// "fit to page", a stretched one, one whose two reds print alike and a
// sheet with one tag's shades swapped are each caught and named. The
// command's side is tests/print_check_test.cc.
#include "chromatag/verify/print_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "calib_sim.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/verify/raster.h"
#include "icc_press.h"
#include "printed_sheet.h"

namespace chromatag {
namespace {

using testing::IccPress;
using testing::PrintAndPhotograph;
using testing::PrintAndScan;
using testing::PrintFn;
using testing::PrintGeometry;
using testing::SimCamera;
using testing::SimScanner;

std::string AllProblems(const PrintPageResult& r) {
  std::string all;
  for (const std::string& p : r.problems) all += "page: " + p + "\n";
  for (const PrintTagResult& t : r.tags) {
    for (const std::string& p : t.problems)
      all += "ID " + std::to_string(t.expected.id) + ": " + p + "\n";
  }
  return all;
}

bool Near(const cv::Vec3b& a, const Rgb8& b) {
  return std::abs(a[2] - b.r) <= 2 && std::abs(a[1] - b.g) <= 2 && std::abs(a[0] - b.b) <= 2;
}

bool Near(const Rgb8& a, const Rgb8& b) {
  return std::abs(a.r - b.r) <= 2 && std::abs(a.g - b.g) <= 2 && std::abs(a.b - b.b) <= 2;
}

// The printed sheet (testing::MakePrintedSheet), made once for the suite.
class PrintCheckTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    sheet_ = testing::MakePrintedSheet("chromatag-print-check", &error).release();
    ASSERT_NE(sheet_, nullptr) << error;
    dir_ = &sheet_->dir;
    record_ = &sheet_->record;
    images_ = &sheet_->images;
    press_ = sheet_->press.get();
    DetectorOptions detector_options;
    detector_options.families = TagFamily::Names();
    detector_options.report_rejected = true;
    detector_ = Detector::Create(detector_options).release();
  }
  static void TearDownTestSuite() {
    delete sheet_;
    delete detector_;
  }

  static double PxPerMm() { return testing::PrintedSheet::PxPerMm(); }

  static PrintPageResult Scan(const cv::Mat& page, const PrintFn& print,
                              const PrintGeometry& geometry = {},
                              const PrintCheckOptions& options = ScanOptions()) {
    SimScanner scanner;
    const cv::Mat scan = PrintAndScan(page, PxPerMm(), print, geometry, scanner);
    return CheckPrintImage(*record_, scan, {"scan", scanner.dpi, scanner.dpi}, *detector_, options);
  }

  static PrintCheckOptions ScanOptions() {
    PrintCheckOptions options;
    options.scans = true;
    return options;
  }

  static inline testing::PrintedSheet* sheet_ = nullptr;
  static inline const std::string* dir_ = nullptr;
  static inline SheetRecord* record_ = nullptr;
  static inline SheetImages* images_ = nullptr;
  static inline IccPress* press_ = nullptr;
  static inline Detector* detector_ = nullptr;
};

TEST_F(PrintCheckTest, GoodSwopPrintOfEveryKeptIdPassesOnEveryPage) {
  ASSERT_EQ(images_->pages.size(), 3u);
  int checked = 0;
  for (size_t page = 0; page < images_->pages.size(); ++page) {
    const PrintPageResult r = Scan(images_->pages[page], press_->AsPrintFn());
    EXPECT_EQ(r.page, static_cast<int>(page));
    EXPECT_NE(r.grade, Grade::kFail) << AllProblems(r);
    EXPECT_NEAR(r.scale_x, 1.0, 0.002);
    EXPECT_NEAR(r.scale_y, 1.0, 0.002);
    EXPECT_EQ(r.tags_found, static_cast<int>(r.tags.size()));
    for (const PrintTagResult& t : r.tags) {
      ++checked;
      EXPECT_TRUE(t.found && t.found_id == t.expected.id && t.hamming == 0)
          << "ID " << t.expected.id;
      // Within 0.15 mm: the detector's corners sit about 0.35 px inside each
      // edge blurred in linear light (0.06 mm at 300 dpi, measured here).
      EXPECT_NEAR(t.size_mm, 30.0, 0.15) << "ID " << t.expected.id;
      ASSERT_TRUE(t.colours.measured);
      // The press keeps the default palette's a* gap near 84 and its green
      // b* gap near 28 (docs/calibration.md's figures), measured on the paper.
      EXPECT_NEAR(t.colours.margins.a_gap, 84.0, 8.0);
      EXPECT_NEAR(t.colours.margins.green_b_gap, 28.0, 5.0);
    }
  }
  EXPECT_EQ(checked, static_cast<int>(record_->tags.size()));
}

TEST_F(PrintCheckTest, FitToPagePrintFailsNamingTheScale) {
  const PrintPageResult r = Scan(images_->pages[0], press_->AsPrintFn(), {0.97, 0.97});
  EXPECT_EQ(r.grade, Grade::kFail);
  EXPECT_NEAR(r.scale_x, 0.970, 0.002);
  EXPECT_NEAR(r.scale_y, 0.970, 0.002);
  EXPECT_LT(r.scale_x_error, 0.001);
  ASSERT_FALSE(r.problems.empty());
  EXPECT_NE(r.problems[0].find("printed at 97.0 % of its size"), std::string::npos)
      << r.problems[0];
  for (const PrintTagResult& t : r.tags) {
    EXPECT_TRUE(t.found && t.hamming == 0);  // The tags themselves are fine...
    EXPECT_NEAR(t.size_mm, 29.1, 0.15);      // ...but 29.1 mm, not 30.
    EXPECT_EQ(t.grade, Grade::kFail);
  }
}

TEST_F(PrintCheckTest, StretchedPrintFailsNamingTheAxis) {
  const PrintPageResult r = Scan(images_->pages[0], press_->AsPrintFn(), {1.0, 1.012});
  EXPECT_EQ(r.grade, Grade::kFail);
  EXPECT_NEAR(r.scale_x, 1.000, 0.002);
  EXPECT_NEAR(r.scale_y, 1.012, 0.002);
  ASSERT_FALSE(r.problems.empty());
  EXPECT_EQ(r.problems[0].rfind("stretched", 0), 0u) << r.problems[0];
}

TEST_F(PrintCheckTest, PrintWhoseRedsPrintAlikeIsNamed) {
  // A press that prints red-1 as red-0: the reds' b* split is gone. The
  // greens alone single out most IDs (the detector's likelihood-ratio read),
  // so the page is found, and each tag read fails as printing its reds alike,
  // not as swapped.
  const TagColors sent = TagColors::FromPalette(record_->palette);
  const Rgb8 red1 = ToRgb8(sent[Shade::kRed1]), red0 = ToRgb8(sent[Shade::kRed0]);
  const PrintFn washed = [&](const Rgb8& c) { return press_->Print(Near(c, red1) ? red0 : c); };
  const PrintPageResult r = Scan(images_->pages[0], washed);
  EXPECT_EQ(r.grade, Grade::kFail);
  EXPECT_EQ(r.page, 0);
  int read = 0;
  for (const PrintTagResult& t : r.tags) {
    EXPECT_EQ(t.grade, Grade::kFail) << "ID " << t.expected.id;
    if (!t.found) continue;
    ++read;
    const std::string problems = AllProblems(r);
    EXPECT_NE(problems.find("ID " + std::to_string(t.expected.id) + ": red shades print alike"),
              std::string::npos)
        << problems;
  }
  EXPECT_GT(read, 0);
  EXPECT_EQ(AllProblems(r).find("swapped"), std::string::npos) << AllProblems(r);
}

// A sheet none of whose tags decodes (every red cell printed as red-0 and
// every green as green-0, so neither colour shows two shades) is not
// recognised, and the candidates the detector gave up on say why.
TEST_F(PrintCheckTest, PrintWhoseShadesAllPrintAlikeIsNamed) {
  const TagColors sent = TagColors::FromPalette(record_->palette);
  const Rgb8 red1 = ToRgb8(sent[Shade::kRed1]), red0 = ToRgb8(sent[Shade::kRed0]);
  const Rgb8 green1 = ToRgb8(sent[Shade::kGreen1]), green0 = ToRgb8(sent[Shade::kGreen0]);
  const PrintFn washed = [&](const Rgb8& c) {
    return press_->Print(Near(c, red1) ? red0 : Near(c, green1) ? green0 : c);
  };
  const PrintPageResult r = Scan(images_->pages[0], washed);
  EXPECT_EQ(r.grade, Grade::kFail);
  EXPECT_EQ(r.page, -1);              // Nothing decodes, so the page cannot be told...
  ASSERT_FALSE(r.undecoded.empty());  // ...but the candidates say why.
  ASSERT_FALSE(r.problems.empty());
  EXPECT_NE(r.problems[0].find("neither colour's two shades can be told apart"), std::string::npos)
      << r.problems[0];
  for (const UndecodedCandidate& u : r.undecoded) {
    EXPECT_LT(u.red_b_split, 4.0);
    EXPECT_LT(u.green_b_split, 4.0);
  }
}

TEST_F(PrintCheckTest, TagWithSwappedShadesIsCaughtAndTheOthersPass) {
  // Tag 3 of page 1 printed with red-1 and red-0 exchanged.
  cv::Mat page = images_->pages[0].clone();
  const PlacedTag& victim = record_->tags[3];
  ASSERT_EQ(victim.page, 0);
  const TagColors sent = TagColors::FromPalette(record_->palette);
  const Rgb8 red1 = ToRgb8(sent[Shade::kRed1]), red0 = ToRgb8(sent[Shade::kRed0]);
  const cv::Point2d tl = MmToPixel(victim.corners_mm[0], PxPerMm()),
                    br = MmToPixel(victim.corners_mm[2], PxPerMm());
  int swapped = 0;
  for (int y = static_cast<int>(tl.y); y <= br.y; ++y) {
    for (int x = static_cast<int>(tl.x); x <= br.x; ++x) {
      cv::Vec3b& p = page.at<cv::Vec3b>(y, x);
      const Rgb8* to = Near(p, red1) ? &red0 : Near(p, red0) ? &red1 : nullptr;
      if (to) p = cv::Vec3b(to->b, to->g, to->r), ++swapped;
    }
  }
  ASSERT_GT(swapped, 1000);
  const PrintPageResult r = Scan(page, press_->AsPrintFn());
  EXPECT_EQ(r.page, 0);
  EXPECT_EQ(r.grade, Grade::kFail);
  for (const PrintTagResult& t : r.tags) {
    if (t.expected.id != victim.id) {
      EXPECT_EQ(t.grade, Grade::kPass) << "ID " << t.expected.id << ": " << AllProblems(r);
      continue;
    }
    EXPECT_EQ(t.grade, Grade::kFail);
    EXPECT_FALSE(t.found && t.found_id == victim.id && t.hamming == 0);
    EXPECT_LT(t.colours.margins.red_b_gap, -10.0);
    std::string all;
    for (const std::string& p : t.problems) all += p + "\n";
    EXPECT_NE(all.find("red shades printed swapped"), std::string::npos) << all;
  }
}

TEST_F(PrintCheckTest, TagPrintedOutOfPlaceIsFlaggedAndLeftOutOfTheFit) {
  // Tag 5 of page 1 moved 3 mm to the right on the page before printing.
  cv::Mat page = images_->pages[0].clone();
  const PlacedTag& moved = record_->tags[5];
  const double quiet = record_->quiet_zone_cells * record_->tag_size_mm / 6.0;
  const cv::Point2d tl =
      MmToPixel({moved.corners_mm[0][0] - quiet, moved.corners_mm[0][1] - quiet}, PxPerMm());
  const int side = static_cast<int>((record_->tag_size_mm + 2 * quiet) * PxPerMm());
  const cv::Rect from(static_cast<int>(tl.x), static_cast<int>(tl.y), side, side);
  const cv::Mat tag = page(from).clone();
  page(from).setTo(cv::Scalar(255, 255, 255));
  tag.copyTo(page(from + cv::Point(static_cast<int>(3.0 * PxPerMm()), 0)));
  const PrintPageResult r = Scan(page, press_->AsPrintFn());
  EXPECT_EQ(r.tags_in_fit, static_cast<int>(r.tags.size()) - 1);
  EXPECT_NEAR(r.scale_x, 1.0, 0.002);
  EXPECT_LT(r.rms_mm, 0.1);
  for (const PrintTagResult& t : r.tags) {
    if (t.expected.id != moved.id) {
      EXPECT_EQ(t.grade, Grade::kPass) << "ID " << t.expected.id << ": " << AllProblems(r);
      continue;
    }
    EXPECT_TRUE(t.found && t.found_id == moved.id);
    EXPECT_NEAR(t.position_error_mm, 3.0, 0.2);
    EXPECT_EQ(t.grade, Grade::kWarn);
    ASSERT_FALSE(t.problems.empty());
    EXPECT_NE(t.problems[0].find("from where the other tags put it"), std::string::npos);
  }
}

TEST_F(PrintCheckTest, PhotoOfAGoodPrintPassesAndAStretchedOneFails) {
  SimCamera camera;
  camera.width = 2400;
  camera.height = 1800;
  // A 1800 px focal length, the page tilted 25 and turned 10 degrees.
  camera.page_corners_px =
      testing::PinholePageCorners(record_->page, 1800, 25, 10, 420, {camera.width, camera.height});
  camera.gains = {1.15, 1.0, 0.8};            // Indoor light.
  for (const double stretch : {1.0, 1.04}) {  // y printed 4 % longer.
    const cv::Mat photo = PrintAndPhotograph(images_->pages[1], PxPerMm(), press_->AsPrintFn(),
                                             {1.0, stretch}, camera);
    const PrintPageResult r =
        CheckPrintImage(*record_, photo, {"photo"}, *detector_, PrintCheckOptions());
    EXPECT_EQ(r.page, 1);
    EXPECT_FALSE(r.scan);
    EXPECT_EQ(r.tags_found, static_cast<int>(r.tags.size()));
    // Measured: 0.9999 and 0.9614 (true 0.9615), jackknife error 0.0006,
    // the focal length estimated as 1802 px.
    EXPECT_NEAR(r.aspect, 1.0 / stretch, 0.003) << "stretch " << stretch;
    EXPECT_LT(r.aspect_error, 0.002);
    EXPECT_NEAR(r.focal_px, 1800, 40);
    if (stretch == 1.0) {
      EXPECT_NE(r.grade, Grade::kFail) << AllProblems(r);
    } else {
      EXPECT_EQ(r.grade, Grade::kFail);
      ASSERT_FALSE(r.problems.empty());
      EXPECT_EQ(r.problems[0].rfind("stretched", 0), 0u) << r.problems[0];
    }
  }
}

// Tilted about one image axis only, the page's perspective leaves the focal
// length free and the aspect trades with it: a 4 % stretch cannot be told
// apart, so the page's shape must be reported as not checked (not passed);
// the camera's intrinsics pin the aspect, and the stretch fails.
TEST_F(PrintCheckTest, PhotoTiltedAboutOneAxisSaysTheShapeWasNotChecked) {
  SimCamera camera;
  camera.width = 2400;
  camera.height = 1800;
  camera.page_corners_px =
      testing::PinholePageCorners(record_->page, 1800, 30, 0, 420, {camera.width, camera.height});
  const cv::Mat photo =
      PrintAndPhotograph(images_->pages[1], PxPerMm(), press_->AsPrintFn(), {1.0, 1.04}, camera);
  PrintPageResult r = CheckPrintImage(*record_, photo, {"tilted"}, *detector_, PrintCheckOptions());
  EXPECT_EQ(r.tags_found, static_cast<int>(r.tags.size()));
  EXPECT_GT(2 * r.aspect_error, PrintCheckOptions().max_aspect_error) << r.aspect_error;
  EXPECT_FALSE(r.geometry_checked);
  EXPECT_EQ(r.grade, Grade::kWarn) << AllProblems(r);
  bool said = false;
  for (const std::string& p : r.problems)
    said |= p.rfind("the page's shape was not checked", 0) == 0 &&
            p.find("give the camera's intrinsics") != p.npos;
  EXPECT_TRUE(said) << AllProblems(r);
  // The command says so too (tests/print_check_test.cc).
  PrintCheckOptions with_camera;
  with_camera.camera =
      CameraIntrinsics{1800, 1800, (camera.width - 1) / 2.0, (camera.height - 1) / 2.0, {}};
  r = CheckPrintImage(*record_, photo, {"tilted"}, *detector_, with_camera);
  EXPECT_TRUE(r.geometry_checked);
  EXPECT_NEAR(r.aspect, 1.0 / 1.04, 0.003);
  EXPECT_EQ(r.grade, Grade::kFail) << AllProblems(r);
  // A stretch far beyond even that loose error bar still fails.
  const cv::Mat gross =
      PrintAndPhotograph(images_->pages[1], PxPerMm(), press_->AsPrintFn(), {1.0, 1.6}, camera);
  r = CheckPrintImage(*record_, gross, {"gross"}, *detector_, PrintCheckOptions());
  EXPECT_GT(2 * r.aspect_error, PrintCheckOptions().max_aspect_error) << r.aspect_error;
  EXPECT_EQ(r.grade, Grade::kFail) << r.aspect << " ± " << 2 * r.aspect_error << AllProblems(r);
  EXPECT_TRUE(r.geometry_checked);
}

TEST_F(PrintCheckTest, ReportsDrawEveryImage) {
  PrintVerdict verdict;
  verdict.images.push_back(Scan(images_->pages[2], press_->AsPrintFn()));
  verdict.images.push_back(Scan(images_->pages[2], press_->AsPrintFn(), {0.97, 0.97}));
  const std::string pdf = RenderPrintReportPdf(*record_, verdict);
  EXPECT_EQ(pdf.rfind("%PDF", 0), 0u);
  const std::string png = RenderPrintReportPng(*record_, verdict);
  const cv::Mat image =
      cv::imdecode(cv::Mat(1, static_cast<int>(png.size()), CV_8U, const_cast<char*>(png.data())),
                   cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_GT(image.cols, 1.3 * image.rows);  // Two A4 report pages side by side.
  // The failing print's tags are marked red (fail), the good one's green.
  auto count = [&](int x0, int x1, auto is) {
    int n = 0;
    for (int y = 0; y < image.rows; ++y)
      for (int x = x0; x < x1; ++x) n += is(image.at<cv::Vec3b>(y, x));
    return n;
  };
  auto red = [](const cv::Vec3b& p) { return p[2] > 190 && p[1] < 60 && p[0] < 60; };
  auto green = [](const cv::Vec3b& p) { return p[1] > 130 && p[2] < 60 && p[0] < 90; };
  // Only inside the drawn page (1.5 px a point, the page's box from 120 to
  // 620 points down): the verdict and the problem list are coloured too.
  const cv::Rect view_box(0, 180, image.cols, 750);
  const cv::Mat page_area = image(view_box);
  auto count_in = [&](int x0, int x1, auto is) {
    int n = 0;
    for (int y = 0; y < page_area.rows; ++y)
      for (int x = x0; x < x1; ++x) n += is(page_area.at<cv::Vec3b>(y, x));
    return n;
  };
  const int half = image.cols / 2;
  EXPECT_GT(count_in(0, half, green), 500);
  EXPECT_LT(count(0, half, red), 50);
  EXPECT_GT(count_in(half, image.cols, red), 500);
}

TEST_F(PrintCheckTest, PhotoFaceOnGuessesTheFocalLengthAndFewTagsLeaveTheAspectUnjudged) {
  // A scan looked at as a photo: face on, so no focal length can be told.
  SimScanner scanner;
  const cv::Mat scan = PrintAndScan(images_->pages[0], PxPerMm(), press_->AsPrintFn(), {}, scanner);
  PrintPageResult r = CheckPrintImage(*record_, scan, {"face-on"}, *detector_, PrintCheckOptions());
  EXPECT_EQ(r.focal_source, "guessed");
  EXPECT_NEAR(r.aspect, 1.0, 0.003);
  EXPECT_NE(r.grade, Grade::kFail) << AllProblems(r);
  EXPECT_TRUE(r.geometry_checked) << AllProblems(r);
  // Given the camera, its focal length is used.
  PrintCheckOptions with_camera;
  with_camera.camera =
      CameraIntrinsics{2000, 2000, (scan.cols - 1) / 2.0, (scan.rows - 1) / 2.0, {}};
  r = CheckPrintImage(*record_, scan, {"face-on"}, *detector_, with_camera);
  EXPECT_EQ(r.focal_source, "camera");
  EXPECT_NEAR(r.aspect, 1.0, 0.003);
  // Page 3 holds four tags; with one blanked out, three are too few.
  cv::Mat page = images_->pages[2].clone();
  const PlacedTag* first = nullptr;
  for (const PlacedTag& t : record_->tags)
    if (t.page == 2 && !first) first = &t;
  const cv::Point2d tl = MmToPixel(first->corners_mm[0], PxPerMm()),
                    br = MmToPixel(first->corners_mm[2], PxPerMm());
  page(cv::Rect(cv::Point(tl), cv::Point(br))).setTo(cv::Scalar(255, 255, 255));
  const cv::Mat few = PrintAndScan(page, PxPerMm(), press_->AsPrintFn(), {}, scanner);
  r = CheckPrintImage(*record_, few, {"few"}, *detector_, PrintCheckOptions());
  EXPECT_EQ(r.tags_in_fit, 3);
  EXPECT_EQ(r.aspect, 0.0);
  EXPECT_FALSE(r.geometry_checked);
  bool said = false;
  for (size_t i = 0; i < r.problems.size(); ++i)
    said |= r.problems[i].find("too few to judge its aspect") != std::string::npos &&
            r.problem_grades[i] == Grade::kWarn;
  EXPECT_TRUE(said) << AllProblems(r);
}

}  // namespace
}  // namespace chromatag
