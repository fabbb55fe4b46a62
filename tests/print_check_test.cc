// verify --print on simulated scans and photos of sheets printed
// through a real press profile (icc_press.h): a good print passes; a print
// shrunk by "fit to page", a stretched one, one whose two reds print alike
// and a sheet with one tag's shades swapped are each caught and named.
#include "chromatag/verify/print_check.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib_sim.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/verify/raster.h"
#include "icc_press.h"
#include "test_util.h"

namespace chromatag {
namespace {

namespace fs = std::filesystem;
using testing::IccPress;
using testing::PrintAndPhotograph;
using testing::PrintAndScan;
using testing::PrintFn;
using testing::PrintGeometry;
using testing::SimCamera;
using testing::SimScanner;

constexpr double kRasterDpi = 300.0;

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

// One IFD entry of an EXIF block, one value: a RATIONAL (type 5) a / b or a
// SHORT (type 3) a.
struct IfdEntry {
  uint16_t tag, type;
  uint32_t a, b;
};

// IFD0's resolution entries: XResolution, YResolution and, unless 0,
// ResolutionUnit.
std::vector<IfdEntry> Resolution(uint32_t x_num, uint32_t x_den, uint32_t y_num, uint32_t y_den,
                                 uint32_t unit) {
  std::vector<IfdEntry> entries{{282, 5, x_num, x_den}, {283, 5, y_num, y_den}};
  if (unit) entries.push_back({296, 3, unit, 0});
  return entries;
}

// A JPEG APP1 segment holding EXIF as cameras write it: "Exif\0\0", a TIFF
// header in either byte order, the IFDs chained (IFD0 first, then IFD1, the
// thumbnail's), the rationals after them.
std::string ExifApp1(const std::vector<std::vector<IfdEntry>>& ifds, bool little = true) {
  auto u16 = [little](uint32_t v) {
    const char lo = static_cast<char>(v), hi = static_cast<char>(v >> 8);
    return little ? std::string{lo, hi} : std::string{hi, lo};
  };
  auto u32 = [&](uint32_t v) {
    return little ? u16(v & 0xFFFF) + u16(v >> 16) : u16(v >> 16) + u16(v & 0xFFFF);
  };
  uint32_t data_at = 8;
  for (const auto& ifd : ifds) data_at += 2 + 12 * static_cast<uint32_t>(ifd.size()) + 4;
  std::string tiff = std::string(little ? "II" : "MM") + u16(42) + u32(8), data;
  uint32_t next = 8;
  for (size_t i = 0; i < ifds.size(); ++i) {
    tiff += u16(static_cast<uint32_t>(ifds[i].size()));
    for (const IfdEntry& e : ifds[i]) {
      tiff += u16(e.tag) + u16(e.type) + u32(1);
      if (e.type == 5) {
        tiff += u32(data_at + static_cast<uint32_t>(data.size()));
        data += u32(e.a) + u32(e.b);
      } else {
        tiff += u16(e.a) + u16(0);
      }
    }
    next += 2 + 12 * static_cast<uint32_t>(ifds[i].size()) + 4;
    tiff += u32(i + 1 < ifds.size() ? next : 0);
  }
  const std::string payload = std::string("Exif\0\0", 6) + tiff + data;
  const size_t length = payload.size() + 2;
  return std::string("\xFF\xE1", 2) + static_cast<char>(length >> 8) +
         static_cast<char>(length & 0xFF) + payload;
}

// A JFIF APP0 segment: density x by y in `units` (0 aspect only, 1 dots per
// inch, 2 per centimetre).
std::string JfifApp0(int units, int x, int y) {
  std::string app0("\xFF\xE0\x00\x10JFIF\x00\x01\x01", 11);
  for (int v : {units, x >> 8, x & 0xFF, y >> 8, y & 0xFF, 0, 0}) app0 += static_cast<char>(v);
  return app0;
}

// `image` as a JPEG whose segments before OpenCV's tables are `app0` then
// `app1` (either "" for none), in place of OpenCV's JFIF APP0.
std::string JpegWith(const cv::Mat& image, const std::string& app0, const std::string& app1) {
  std::vector<uint8_t> encoded;
  cv::imencode(".jpg", image, encoded, {cv::IMWRITE_JPEG_QUALITY, 95});
  const std::string jpeg(encoded.begin(), encoded.end());
  EXPECT_EQ(jpeg.compare(0, 4, "\xFF\xD8\xFF\xE0", 4), 0);
  const size_t app0_end =
      4 + (static_cast<unsigned char>(jpeg[4]) << 8 | static_cast<unsigned char>(jpeg[5]));
  return jpeg.substr(0, 2) + app0 + app1 + jpeg.substr(app0_end);
}

// Where a page's corners land in a pinhole camera (square pixels, principal
// point at the centre, focal length f px) looking at the page's centre from
// `distance_mm`, the page turned by `tilt_deg` about its horizontal axis and
// `yaw_deg` about its vertical one: a perspective a real camera can make.
std::array<cv::Point2d, 4> PinholePageCorners(const PageSize& page, double f, double tilt_deg,
                                              double yaw_deg, double distance_mm, cv::Size size) {
  const double t = tilt_deg * CV_PI / 180, y = yaw_deg * CV_PI / 180;
  const cv::Matx33d rx(1, 0, 0, 0, std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t));
  const cv::Matx33d ry(std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y));
  std::array<cv::Point2d, 4> out;
  const double w = page.width_mm / 2, h = page.height_mm / 2;
  const cv::Vec3d corners[4] = {{-w, -h, 0}, {w, -h, 0}, {w, h, 0}, {-w, h, 0}};
  for (int i = 0; i < 4; ++i) {
    const cv::Vec3d p = ry * rx * corners[i] + cv::Vec3d(0, 0, distance_mm);
    out[i] = {f * p[0] / p[2] + (size.width - 1) / 2.0, f * p[1] / p[2] + (size.height - 1) / 2.0};
  }
  return out;
}

// Every kept 16h5 ID at 30 mm on A4 (three pages), generated once, with its
// pages rasterised at 300 dpi, and the SWOP press.
class PrintCheckTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(fs::temp_directory_path() /
                           ("chromatag-print-check-" + std::to_string(getpid())));
    fs::create_directories(*dir_);
    SheetOptions options;
    options.family = TagFamily::Load("16h5");
    options.ids = options.family->kept_ids();
    options.palette = *BuiltinPalette("default");
    options.tag_size_mm = 30.0;
    std::string error;
    const std::string sheet = *dir_ + "/tags.pdf";
    ASSERT_TRUE(WriteSheet(options, sheet, &error)) << error;
    auto record = ReadSidecar(SidecarPath(sheet), &error);
    ASSERT_TRUE(record) << error;
    record_ = new SheetRecord(*record);
    auto images = RasterizeSheet(*record_, kRasterDpi, &error);
    ASSERT_TRUE(images) << error;
    images_ = new SheetImages(*images);
    press_ = IccPress::Load(IccPress::DefaultCmykProfilePath(), &error).release();
    ASSERT_NE(press_, nullptr) << error;
    DetectorOptions detector_options;
    detector_options.families = TagFamily::Names();
    detector_options.report_rejected = true;
    detector_ = Detector::Create(detector_options).release();
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
    delete record_;
    delete images_;
    delete press_;
    delete detector_;
  }

  static double PxPerMm() { return kRasterDpi / 25.4; }

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

  static inline std::string* dir_ = nullptr;
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
  // A press that prints red-1 as red-0: the reds' b* split is gone.
  const TagColors sent = TagColors::FromPalette(record_->palette);
  const Rgb8 red1 = ToRgb8(sent[Shade::kRed1]), red0 = ToRgb8(sent[Shade::kRed0]);
  const PrintFn washed = [&](const Rgb8& c) { return press_->Print(Near(c, red1) ? red0 : c); };
  const PrintPageResult r = Scan(images_->pages[0], washed);
  EXPECT_EQ(r.grade, Grade::kFail);
  EXPECT_EQ(r.page, -1);              // Nothing decodes, so the page cannot be told...
  ASSERT_FALSE(r.undecoded.empty());  // ...but the candidates say why.
  ASSERT_FALSE(r.problems.empty());
  EXPECT_NE(r.problems[0].find("the two reds print alike"), std::string::npos) << r.problems[0];
  for (const UndecodedCandidate& u : r.undecoded) {
    EXPECT_LT(u.red_b_split, 4.0);
    EXPECT_GT(u.green_b_split, 15.0);
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
      PinholePageCorners(record_->page, 1800, 25, 10, 420, {camera.width, camera.height});
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
      PinholePageCorners(record_->page, 1800, 30, 0, 420, {camera.width, camera.height});
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
  // The command's verdict says so too.
  const std::string file = *dir_ + "/tilted.png";
  ASSERT_TRUE(cv::imwrite(file, photo));
  const auto run = testing::RunChromatag({"verify", *dir_ + "/tags.pdf", "--print", file});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("pass; the page's shape was not checked. PASS with warnings"),
            std::string::npos)
      << run.out;
  // In the command line's terms (cli/flag_terms.cc).
  EXPECT_NE(run.out.find("give --camera, add a photo"), std::string::npos) << run.out;
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

TEST(ReadImageDpiTest, PngPhysJpegJfifAndTiff) {
  // A PNG header with a pHYs chunk of 11811 pixels per metre (300 dpi).
  std::string png("\x89PNG\r\n\x1a\n", 8);
  auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  png += be32(13) + "IHDR" + std::string(13, '\0') + be32(0);
  png += be32(9) + "pHYs" + be32(11811) + be32(23622) + std::string(1, '\1') + be32(0);
  const auto dpi = ReadImageDpi(png);
  ASSERT_TRUE(dpi);
  EXPECT_NEAR((*dpi)[0], 300.0, 0.01);
  EXPECT_NEAR((*dpi)[1], 600.0, 0.01);
  // Unit 0 (aspect only) and a truncated chunk record no resolution.
  std::string aspect_only = png;
  aspect_only[8 + 25 + 16] = '\0';
  EXPECT_FALSE(ReadImageDpi(aspect_only));
  EXPECT_FALSE(ReadImageDpi(png.substr(0, 40)));
  // A JPEG's JFIF APP0 in dots per centimetre, and OpenCV's own (aspect only).
  std::string jpeg("\xFF\xD8\xFF\xE0\x00\x10JFIF\x00\x01\x02\x02\x00\x76\x00\x76\x00\x00", 20);
  const auto jdpi = ReadImageDpi(jpeg);
  ASSERT_TRUE(jdpi);
  EXPECT_NEAR((*jdpi)[0], 118 * 2.54, 0.01);
  std::vector<uint8_t> encoded;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(255, 255, 255)), encoded);
  EXPECT_FALSE(ReadImageDpi(std::string(encoded.begin(), encoded.end())));
  // TIFF, little-endian, 300 x 600 dpi; big-endian in centimetres.
  const std::string tiff_le(
      "II*\0\x08\0\0\0"                     // Header, IFD at 8.
      "\x03\0"                              // Three entries.
      "\x1a\x01\x05\0\x01\0\0\0\x32\0\0\0"  // XResolution at 50.
      "\x1b\x01\x05\0\x01\0\0\0\x3a\0\0\0"  // YResolution at 58.
      "\x28\x01\x03\0\x01\0\0\0\x02\0\0\0"  // ResolutionUnit inch.
      "\0\0\0\0"                            // No next IFD.
      "\x2c\x01\0\0\x01\0\0\0"              // 300 / 1.
      "\x58\x02\0\0\x01\0\0\0",             // 600 / 1.
      66);
  const auto tdpi = ReadImageDpi(tiff_le);
  ASSERT_TRUE(tdpi);
  EXPECT_DOUBLE_EQ((*tdpi)[0], 300.0);
  EXPECT_DOUBLE_EQ((*tdpi)[1], 600.0);
  const std::string tiff_be(
      "MM\0*\0\0\0\x08"
      "\0\x03"
      "\x01\x1a\0\x05\0\0\0\x01\0\0\0\x32"
      "\x01\x1b\0\x05\0\0\0\x01\0\0\0\x3a"
      "\x01\x28\0\x03\0\0\0\x01\0\x03\0\0"
      "\0\0\0\0"
      "\0\0\0\x76\0\0\0\x01"
      "\0\0\0\x76\0\0\0\x01",
      66);
  const auto bdpi = ReadImageDpi(tiff_be);
  ASSERT_TRUE(bdpi);
  EXPECT_NEAR((*bdpi)[0], 118 * 2.54, 1e-9);
  EXPECT_FALSE(ReadImageDpi(tiff_le.substr(0, 30)));  // Cut inside the IFD.
  EXPECT_FALSE(ReadImageDpi("not an image"));
  EXPECT_FALSE(ReadImageDpi(""));
}

TEST(ReadImageDpiTest, JpegExifInInchesWithoutJfif) {
  // As cameras and most scanners write it: EXIF only. The file still decodes.
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string jpeg = JpegWith(white, "", ExifApp1({Resolution(300, 1, 300, 1, 2)}));
  const cv::Mat raw(1, static_cast<int>(jpeg.size()), CV_8U, const_cast<char*>(jpeg.data()));
  EXPECT_EQ(cv::imdecode(raw, cv::IMREAD_COLOR).size(), white.size());
  const auto dpi = ReadImageDpi(jpeg);
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 300.0);
  EXPECT_DOUBLE_EQ((*dpi)[1], 300.0);
  // Big-endian (Motorola), no ResolutionUnit (inch by default), x and y apart.
  const auto be =
      ReadImageDpi(JpegWith(white, "", ExifApp1({Resolution(600, 2, 1200, 2, 0)}, false)));
  ASSERT_TRUE(be);
  EXPECT_DOUBLE_EQ((*be)[0], 300.0);
  EXPECT_DOUBLE_EQ((*be)[1], 600.0);
}

TEST(ReadImageDpiTest, JpegExifInCentimetres) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto dpi =
      ReadImageDpi(JpegWith(white, "", ExifApp1({Resolution(11811, 100, 11811, 100, 3)})));
  ASSERT_TRUE(dpi);
  EXPECT_NEAR((*dpi)[0], 300.0, 0.01);
  EXPECT_NEAR((*dpi)[1], 300.0, 0.01);
}

TEST(ReadImageDpiTest, JpegExifBeforeJfif) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string exif600 = ExifApp1({Resolution(600, 1, 600, 1, 2)});
  // JFIF aspect only (units 0, as OpenCV and many cameras write) and EXIF 600.
  auto dpi = ReadImageDpi(JpegWith(white, JfifApp0(0, 1, 1), exif600));
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 600.0);
  // Both record one and they differ: EXIF's, the device's, over JFIF's default.
  dpi = ReadImageDpi(JpegWith(white, JfifApp0(1, 72, 72), exif600));
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 600.0);
  // EXIF without a resolution, or with one in no unit (1): JFIF's.
  const std::vector<IfdEntry> orientation{{274, 3, 1, 0}};
  for (const std::string& exif :
       {ExifApp1({orientation}), ExifApp1({Resolution(600, 1, 600, 1, 1)}),
        ExifApp1({Resolution(600, 0, 600, 0, 2)})}) {
    dpi = ReadImageDpi(JpegWith(white, JfifApp0(2, 118, 118), exif));
    ASSERT_TRUE(dpi);
    EXPECT_NEAR((*dpi)[0], 118 * 2.54, 1e-9);
  }
  // JFIF alone.
  dpi = ReadImageDpi(JpegWith(white, JfifApp0(1, 200, 100), ""));
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 200.0);
  EXPECT_DOUBLE_EQ((*dpi)[1], 100.0);
}

TEST(ReadImageDpiTest, JpegWithoutResolution) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  EXPECT_FALSE(ReadImageDpi(JpegWith(white, "", "")));
  EXPECT_FALSE(ReadImageDpi(JpegWith(white, JfifApp0(0, 1, 1), "")));
  // EXIF with no resolution in IFD0 records none: not libexif's default of
  // 72 dpi, nor the thumbnail's (IFD1).
  const std::vector<IfdEntry> unit_only{{296, 3, 2, 0}};
  EXPECT_FALSE(ReadImageDpi(JpegWith(white, "", ExifApp1({unit_only}))));
  EXPECT_FALSE(ReadImageDpi(
      JpegWith(white, JfifApp0(0, 1, 1), ExifApp1({unit_only, Resolution(72, 1, 72, 1, 2)}))));
}

TEST(ReadImageDpiTest, JpegCorruptExifIsIgnored) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string jfif = JfifApp0(1, 300, 300), exif = ExifApp1({Resolution(600, 1, 600, 1, 2)});
  auto dpi_x = [](const std::string& jpeg) {
    const auto dpi = ReadImageDpi(jpeg);
    return dpi ? (*dpi)[0] : 0.0;
  };
  ASSERT_EQ(dpi_x(JpegWith(white, jfif, exif)), 600.0);
  // The segment's header and nothing usable after it; IFD0 beyond the
  // block; the rationals beyond it; the segment longer than the file.
  std::string no_tiff = exif.substr(0, 10) + "garbage";
  no_tiff[3] = static_cast<char>(no_tiff.size() - 2);
  std::string far_ifd = exif, far_values = exif;
  far_ifd[14] = '\x7F';                 // IFD0's offset, little-endian, low byte.
  far_values[10 + 8 + 2 + 8] = '\xF0';  // XResolution's value offset.
  far_values[10 + 8 + 2 + 12 + 8] = '\xF0';
  for (const std::string& bad : {no_tiff, far_ifd, far_values}) {
    EXPECT_EQ(dpi_x(JpegWith(white, jfif, bad)), 300.0);
    EXPECT_FALSE(ReadImageDpi(JpegWith(white, "", bad)));
  }
  const std::string whole = JpegWith(white, jfif, exif);
  std::string long_segment = whole.substr(0, 20 + exif.size());
  long_segment[20 + 3] = '\x7F';  // Claims more than the file holds.
  EXPECT_EQ(dpi_x(long_segment), 300.0);
  // Cut anywhere, or any byte of the EXIF block broken: JFIF's, EXIF's or
  // none, never a crash.
  for (size_t size = 0; size <= whole.size(); ++size) {
    const double x = dpi_x(whole.substr(0, size));
    EXPECT_TRUE(x == 0.0 || x == 300.0 || x == 600.0) << size << ": " << x;
  }
  for (size_t i = 24; i < 20 + exif.size(); ++i) {
    for (char c : {'\x00', '\xFF'}) {
      std::string broken = whole;
      broken[i] = c;
      const auto dpi = ReadImageDpi(broken);
      EXPECT_TRUE(!dpi || (std::isfinite((*dpi)[0]) && (*dpi)[0] > 0)) << i;
    }
  }
}

TEST_F(PrintCheckTest, CliChecksScansAndReportsAndRefusesBadInput) {
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
