// Printing through a real press profile: Ghostscript's SWOP press
// (default_cmyk.icc) applied with LittleCMS, what it does to the palettes,
// and the geometry of a printed and scanned page.
#include "icc_press.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib_sim.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/tag_renderer.h"
#include "chromatag/layout/calib_sheet_layout.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/raster.h"
#include "test_util.h"

namespace chromatag {
namespace {

namespace fs = std::filesystem;
using testing::CommandResult;
using testing::IccPress;
using testing::PrintAndPhotograph;
using testing::PrintGeometry;
using testing::RunChromatag;
using testing::ScanPixelOfPagePoint;
using testing::SimCamera;
using testing::SimScanner;

// The margins the detector relies on, of a palette as printed.
struct PrintedMargins {
  std::array<Lab, kNumShades> lab;
  double a_gap = 0;        // min a*(reds) - max a*(greens).
  double red_b_gap = 0;    // b*(red-1) - b*(red-0).
  double green_b_gap = 0;  // b*(green-0) - b*(green-1).
};

PrintedMargins Margins(const std::array<Lab, kNumShades>& lab) {
  auto at = [&](Shade s) { return lab[static_cast<int>(s)]; };
  PrintedMargins m;
  m.lab = lab;
  m.a_gap = std::min(at(Shade::kRed1).a, at(Shade::kRed0).a) -
            std::max(at(Shade::kGreen1).a, at(Shade::kGreen0).a);
  m.red_b_gap = at(Shade::kRed1).b - at(Shade::kRed0).b;
  m.green_b_gap = at(Shade::kGreen0).b - at(Shade::kGreen1).b;
  return m;
}

// The palette's file colours (8-bit sRGB, as the generator sends them) as
// designed and as the press prints them.
std::pair<PrintedMargins, PrintedMargins> DesignAndPrint(const std::string& name,
                                                         const IccPress& press) {
  const auto palette = BuiltinPalette(name);
  EXPECT_TRUE(palette);
  const TagColors sent = TagColors::FromPalette(*palette);
  std::array<Lab, kNumShades> design, printed;
  for (Shade s : kAllShades) {
    const Rgb8 rgb = ToRgb8(sent[s]);
    design[static_cast<int>(s)] = SrgbToLab(rgb);
    printed[static_cast<int>(s)] = press.Print(rgb);
  }
  return {Margins(design), Margins(printed)};
}

void Describe(const std::string& name, const PrintedMargins& design,
              const PrintedMargins& printed) {
  std::printf("%s: a* gap %.1f -> %.1f, red b* gap %.1f -> %.1f, green b* gap %.1f -> %.1f\n",
              name.c_str(), design.a_gap, printed.a_gap, design.red_b_gap, printed.red_b_gap,
              design.green_b_gap, printed.green_b_gap);
  for (Shade s : kAllShades) {
    const Lab& d = design.lab[static_cast<int>(s)];
    const Lab& p = printed.lab[static_cast<int>(s)];
    std::printf("  %-8s (%5.1f %6.1f %6.1f) -> (%5.1f %6.1f %6.1f)\n", ShadeName(s), d.L, d.a, d.b,
                p.L, p.a, p.b);
  }
}

std::unique_ptr<IccPress> LoadPress() {
  std::string error;
  auto press = IccPress::Load(IccPress::DefaultCmykProfilePath(), &error);
  EXPECT_TRUE(press) << error;
  return press;
}

TEST(IccPressTest, PaperStaysWhiteAndInkIsNotBlack) {
  const auto press = LoadPress();
  ASSERT_TRUE(press);
  const Lab paper = press->Print(Rgb8{255, 255, 255});
  EXPECT_NEAR(paper.L, 100.0, 0.5);
  EXPECT_NEAR(paper.a, 0.0, 0.5);
  EXPECT_NEAR(paper.b, 0.0, 0.5);
  // A press's black is ink on paper, far from L* 0.
  const Lab black = press->Print(Rgb8{0, 0, 0});
  EXPECT_GT(black.L, 5.0);
  EXPECT_LT(black.L, 30.0);
  // Cached values are the same values.
  const Lab again = press->Print(Rgb8{0, 0, 0});
  EXPECT_EQ(again.L, black.L);
}

// The figures: the press keeps default's a* gap (about 84) but turns
// green-0 from b* 55 to about 31 (green b* gap about 28 against spec section
// 6's design goal of 35), and leaves iccv17 red and green b* gaps of only
// about 8 and 11. Measured here (relative colorimetric, no black point
// compensation, D50 adapted to D65 by Bradford): default a* gap 114.7 ->
// 88.1, red b* gap 55.4 -> 38.1, green b* gap 51.6 -> 27.4, green-0 b* 54.9
// -> 31.1; iccv17 a* gap 57.8 -> 58.1, b* gaps 7.6 -> 7.8 and 11.1 -> 11.4.
// The a* gap is the one figure that differs from the issue's: read in the
// press's own D50 CIELAB, without the adaptation, it is 83.8.
TEST(IccPressTest, WhatThePressDoesToThePalettes) {
  const auto press = LoadPress();
  ASSERT_TRUE(press);
  const auto [def_design, def_printed] = DesignAndPrint("default", *press);
  Describe("default", def_design, def_printed);
  const Lab design_green0 = def_design.lab[static_cast<int>(Shade::kGreen0)];
  const Lab printed_green0 = def_printed.lab[static_cast<int>(Shade::kGreen0)];
  EXPECT_NEAR(design_green0.b, 55.0, 1.0);
  EXPECT_NEAR(printed_green0.b, 31.0, 1.0);
  EXPECT_NEAR(def_printed.a_gap, 88.0, 2.0);
  EXPECT_NEAR(def_printed.red_b_gap, 38.0, 2.0);
  EXPECT_NEAR(def_printed.green_b_gap, 28.0, 1.5);
  EXPECT_LT(def_printed.green_b_gap, 35.0);  // Below the design goal.

  const auto [iccv_design, iccv_printed] = DesignAndPrint("iccv17", *press);
  Describe("iccv17", iccv_design, iccv_printed);
  EXPECT_NEAR(iccv_printed.a_gap, 58.0, 2.0);
  EXPECT_NEAR(iccv_printed.red_b_gap, 8.0, 1.0);
  EXPECT_NEAR(iccv_printed.green_b_gap, 11.0, 1.0);
  // Where the press hurts most: iccv17's b* gaps are the thinnest margins.
  EXPECT_LT(iccv_printed.red_b_gap, def_printed.red_b_gap / 3);
  EXPECT_LT(iccv_printed.green_b_gap, def_printed.green_b_gap / 2);
}

TEST(IccPressTest, RefusesMissingAndNonCmykProfiles) {
  std::string error;
  EXPECT_EQ(IccPress::Load("/nonexistent/press.icc", &error), nullptr);
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
  EXPECT_NE(error.find("/nonexistent/press.icc"), std::string::npos) << error;
  error.clear();
  EXPECT_EQ(IccPress::Load("/usr/share/color/icc/ghostscript/srgb.icc", &error), nullptr);
  EXPECT_NE(error.find("not a CMYK output"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

// A white page of `size_mm` at `px_per_mm` with black dots of radius 1.5 mm.
cv::Mat PageWithDots(const cv::Size2d& size_mm, double px_per_mm,
                     const std::vector<cv::Point2d>& dots_mm) {
  cv::Mat page(static_cast<int>(std::lround(size_mm.height * px_per_mm)),
               static_cast<int>(std::lround(size_mm.width * px_per_mm)), CV_8UC3,
               cv::Scalar::all(255));
  constexpr int kShift = 8;  // Sub-pixel centres for cv::circle.
  for (const cv::Point2d& d : dots_mm) {
    const cv::Point2d px = d * px_per_mm - cv::Point2d(0.5, 0.5);
    cv::circle(page,
               cv::Point(std::lround(px.x * (1 << kShift)), std::lround(px.y * (1 << kShift))),
               static_cast<int>(std::lround(1.5 * px_per_mm * (1 << kShift))), cv::Scalar::all(0),
               cv::FILLED, cv::LINE_AA, kShift);
  }
  return page;
}

// Centroid of the darkness (paper level minus pixel) in a window around
// `guess`, pixel centres at integers.
cv::Point2d DarkCentroid(const cv::Mat& scan, const cv::Point2d& guess, int radius) {
  cv::Mat grey;
  cv::cvtColor(scan, grey, cv::COLOR_BGR2GRAY);
  const cv::Rect window(std::lround(guess.x) - radius, std::lround(guess.y) - radius,
                        2 * radius + 1, 2 * radius + 1);
  // The paper's level: the window's border.
  double paper = 0;
  int n = 0;
  for (int y = window.y; y < window.br().y; ++y) {
    for (int x = window.x; x < window.br().x; ++x) {
      if (y == window.y || x == window.x || y == window.br().y - 1 || x == window.br().x - 1) {
        paper += grey.at<uint8_t>(y, x);
        ++n;
      }
    }
  }
  paper /= n;
  double sum = 0, sx = 0, sy = 0;
  for (int y = window.y; y < window.br().y; ++y) {
    for (int x = window.x; x < window.br().x; ++x) {
      const double w = std::max(0.0, paper - grey.at<uint8_t>(y, x));
      sum += w;
      sx += w * x;
      sy += w * y;
    }
  }
  return {sx / sum, sy / sum};
}

TEST(IccPressTest, ScanGeometryIsExact) {
  const auto press = LoadPress();
  ASSERT_TRUE(press);
  const cv::Size2d page_mm(100, 140);
  const double px_per_mm = 20;
  const std::vector<cv::Point2d> dots = {{10, 12}, {90, 12}, {50, 70}, {12, 130}, {88, 128}};
  const cv::Mat page = PageWithDots(page_mm, px_per_mm, dots);
  SimScanner scanner;
  scanner.rotation_deg = 2.0;
  scanner.offset_mm = {6.0, 4.0};
  scanner.glass_width_mm = 120;
  scanner.glass_height_mm = 160;
  for (const PrintGeometry geometry :
       {PrintGeometry{}, PrintGeometry{0.97, 0.97}, PrintGeometry{1.0, 1.01}}) {
    const cv::Mat scan = PrintAndScan(page, px_per_mm, press->AsPrintFn(), geometry, scanner);
    ASSERT_EQ(scan.cols, std::lround(120 / 25.4 * scanner.dpi));
    ASSERT_EQ(scan.rows, std::lround(160 / 25.4 * scanner.dpi));
    for (const cv::Point2d& d : dots) {
      const cv::Point2d expected = ScanPixelOfPagePoint(d, page_mm, geometry, scanner);
      const cv::Point2d seen = DarkCentroid(scan, expected, 30);
      EXPECT_NEAR(seen.x, expected.x, 0.1) << d << " scale " << geometry.scale_x;
      EXPECT_NEAR(seen.y, expected.y, 0.1) << d << " scale " << geometry.scale_y;
    }
  }
  // Fit to page at 0.97 shrinks what is printed by 3 %: two dots 80 mm apart
  // land 0.97 * 80 mm apart on the scan.
  const cv::Mat fitted =
      PrintAndScan(page, px_per_mm, press->AsPrintFn(), PrintGeometry{0.97, 0.97}, scanner);
  const double px_per_mm_scan = scanner.dpi / 25.4;
  const cv::Point2d a =
      DarkCentroid(fitted, ScanPixelOfPagePoint(dots[0], page_mm, {0.97, 0.97}, scanner), 30);
  const cv::Point2d b =
      DarkCentroid(fitted, ScanPixelOfPagePoint(dots[1], page_mm, {0.97, 0.97}, scanner), 30);
  EXPECT_NEAR(cv::norm(b - a) / px_per_mm_scan, 0.97 * 80.0, 0.01);
}

TEST(IccPressTest, ScanShowsPaperPrintAndLid) {
  const auto press = LoadPress();
  ASSERT_TRUE(press);
  const cv::Size2d page_mm(60, 80);
  const double px_per_mm = 12;
  cv::Mat page = PageWithDots(page_mm, px_per_mm, {});
  SimScanner scanner;
  scanner.rotation_deg = 0;
  scanner.offset_mm = {10, 10};
  scanner.glass_width_mm = 80;
  scanner.glass_height_mm = 100;
  scanner.noise_sigma = 0;
  const cv::Mat scan = PrintAndScan(page, px_per_mm, press->AsPrintFn(), PrintGeometry{}, scanner);
  const double paper = scan.at<cv::Vec3b>(scan.rows / 2, scan.cols / 2)[1];
  const double lid = scan.at<cv::Vec3b>(5, 5)[1];
  EXPECT_NEAR(paper, 255.0 * LinearToSrgb(scanner.exposure), 1.0);
  EXPECT_NEAR(lid, 255.0 * LinearToSrgb(0.85 * scanner.exposure), 1.0);
}

// The calibration end to end through the press: the calibration
// sheet printed through the SWOP press and photographed under tungsten and
// daylight, `chromatag calibrate` on the photos, a tag sheet in the chosen
// palette printed through the same press and photographed the same way, and
// `chromatag detect --config` on those photos.
//
// Measured (lscpu: "Intel(R) Xeon(R) Processor", 2 cores, Release): with the
// derived config every one of the 28 tags is found under both lights for
// both palettes, no bit corrected, nothing else detected. The default
// detector options find them all too, on the sheets in the calibrated
// palettes and on those in default and iccv17 themselves: at 75 px a tag the
// press does not take the margins below the detector's defaults. What the
// calibration buys is margin, through the palette: the worst decision margin
// over the sheet (tungsten, daylight) is 20.1 and 24.7 for default, 29.4 and
// 37.7 for the palette calibrated from it; 5.4 and 6.6 for iccv17, 28.5 and
// 35.6 for the palette calibrated from it.
class IccCalibrationTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(fs::temp_directory_path() /
                           ("chromatag-icc-press-" + std::to_string(getpid())));
    fs::create_directories(*dir_);
    std::string error;
    press_ = IccPress::Load(IccPress::DefaultCmykProfilePath(), &error).release();
    ASSERT_NE(press_, nullptr) << error;
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    if (std::getenv("CHROMATAG_KEEP_TEST_OUTPUT") == nullptr) fs::remove_all(*dir_, ignored);
    delete dir_;
    delete press_;
  }

  using Light = testing::NamedCamera;
  static std::vector<Light> Lights() { return testing::TungstenAndDaylight(); }

  // Photographs `page` (at px_per_mm) printed through the press under each
  // light; returns the PNGs' paths, in the order of Lights().
  static std::vector<std::string> Photograph(const cv::Mat& page, double px_per_mm,
                                             const std::string& prefix) {
    std::vector<std::string> paths;
    for (const Light& light : Lights()) {
      const std::string path = *dir_ + "/" + prefix + "-" + light.name + ".png";
      EXPECT_TRUE(cv::imwrite(
          path, PrintAndPhotograph(page, px_per_mm, press_->AsPrintFn(), {}, light.camera)));
      paths.push_back(path);
    }
    return paths;
  }

  // calib-sheet for `palette`, printed, photographed under each light and
  // calibrated into `*out`.
  static CommandResult Calibrate(const std::string& palette, std::string* out) {
    const std::string sheet = *dir_ + "/calib-" + palette + ".pdf";
    const CommandResult made = RunChromatag({"calib-sheet", "-o", sheet, "--palette", palette});
    EXPECT_EQ(made.exit_code, 0) << made.err;
    std::string error;
    const auto layout = ReadCalibSidecar(sheet + ".json", &error);
    EXPECT_TRUE(layout) << error;
    if (!layout) return {};
    constexpr double kPxPerMm = 6.0;  // Finer than the photos' 3.9.
    const std::vector<std::string> photos =
        Photograph(RasterizeCalibPage(*layout, kPxPerMm), kPxPerMm, "calib-" + palette);
    *out = *dir_ + "/calibrated-" + palette;
    std::vector<std::string> args = {"calibrate"};
    args.insert(args.end(), photos.begin(), photos.end());
    args.insert(args.end(), {"--sheet", sheet + ".json", "-o", *out});
    return RunChromatag(args);
  }

  struct Found {
    int id = -1;
    int hamming = -1;
    double margin = 0;  // The detector's decision margin.
    cv::Point2d centre;
  };

  // What detect made of one photo of a tag sheet.
  struct Outcome {
    int expected = 0;  // Tags on the sheet.
    int right = 0;     // Found where the sidecar puts them, no bit corrected.
    double min_margin = 0;
    std::string problems;  // Missed, misplaced, corrected or repeated.
  };

  struct PrintedSheet {
    std::optional<SheetRecord> record;
    std::vector<std::string> photos;  // In the order of Lights().
  };

  // Every kept 16h5 ID at 20 mm (28 tags, one A4 page) in the palette
  // `palette_args` name, generated by the CLI, printed and photographed under
  // each light.
  static PrintedSheet PrintSheet(const std::vector<std::string>& palette_args,
                                 const std::string& name) {
    const std::string sheet = *dir_ + "/tags-" + name + ".pdf";
    std::vector<std::string> args = {"generate", "--family", "16h5", "--all",
                                     "--size",   "20mm",     "-o",   sheet};
    args.insert(args.end(), palette_args.begin(), palette_args.end());
    const CommandResult made = RunChromatag(args);
    EXPECT_EQ(made.exit_code, 0) << made.err;
    std::string error;
    PrintedSheet printed;
    printed.record = ReadSidecar(SidecarPath(sheet), &error);
    EXPECT_TRUE(printed.record) << error;
    if (!printed.record) return printed;
    const auto images = RasterizeSheet(*printed.record, 150.0, &error);
    EXPECT_TRUE(images) << error;
    if (!images) return printed;
    EXPECT_EQ(images->pages.size(), 1u);
    printed.photos = Photograph(images->pages[0], images->px_per_mm, "tags-" + name);
    return printed;
  }

  // `chromatag detect` with `detect_args` on each photo of `sheet`.
  static std::vector<Outcome> Detect(const PrintedSheet& sheet,
                                     const std::vector<std::string>& detect_args) {
    std::vector<Outcome> outcomes;
    const std::vector<Light> lights = Lights();
    for (size_t i = 0; i < sheet.photos.size(); ++i) {
      std::vector<std::string> detect = {"detect", "--json", "--family", "16h5"};
      detect.insert(detect.end(), detect_args.begin(), detect_args.end());
      detect.push_back(sheet.photos[i]);
      const CommandResult r = RunChromatag(detect);
      EXPECT_EQ(r.exit_code, 0) << r.err;
      outcomes.push_back(Score(*sheet.record, lights[i].camera, ParseDetections(r.out)));
    }
    return outcomes;
  }

  static std::vector<Found> ParseDetections(const std::string& out) {
    std::vector<Found> found;
    std::istringstream lines(out);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.empty() || line[0] != '{') continue;
      const nlohmann::json frame = nlohmann::json::parse(line);
      for (const auto& d : frame.at("detections")) {
        Found f;
        f.id = d.at("id");
        f.hamming = d.at("hamming");
        f.margin = d.at("margin");
        for (const auto& c : d.at("corners")) f.centre += cv::Point2d(c[0], c[1]) * 0.25;
        found.push_back(f);
      }
    }
    return found;
  }

  // Matches detections against the sheet's tags; the page's corners land at
  // camera.page_corners_px.
  static Outcome Score(const SheetRecord& record, const SimCamera& camera,
                       const std::vector<Found>& found) {
    const float w = static_cast<float>(record.page.width_mm);
    const float h = static_cast<float>(record.page.height_mm);
    const cv::Point2f page[4] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
    cv::Point2f photo[4];
    for (int i = 0; i < 4; ++i) photo[i] = cv::Point2f(camera.page_corners_px[i]);
    const cv::Matx33d photo_from_page = cv::getPerspectiveTransform(page, photo);
    std::map<int, cv::Point2d> where;
    for (const PlacedTag& tag : record.tags) {
      const cv::Vec3d p = photo_from_page * cv::Vec3d(tag.center_mm[0], tag.center_mm[1], 1);
      where[tag.id] = {p[0] / p[2], p[1] / p[2]};
    }
    Outcome outcome;
    outcome.expected = static_cast<int>(record.tags.size());
    outcome.min_margin = std::numeric_limits<double>::infinity();
    std::map<int, int> seen;
    for (const Found& f : found) {
      const auto it = where.find(f.id);
      const bool placed = it != where.end() && cv::norm(it->second - f.centre) < 4.0;
      if (placed && f.hamming == 0 && ++seen[f.id] == 1) {
        ++outcome.right;
        outcome.min_margin = std::min(outcome.min_margin, f.margin);
      } else {
        outcome.problems += "ID " + std::to_string(f.id) + " hamming " + std::to_string(f.hamming) +
                            (placed ? "" : " misplaced") + "; ";
      }
    }
    for (const auto& [id, centre] : where) {
      if (seen[id] == 0) outcome.problems += "ID " + std::to_string(id) + " missed; ";
    }
    return outcome;
  }

  static void Print(const std::string& what, const std::vector<Outcome>& outcomes) {
    const std::vector<Light> lights = Lights();
    for (size_t i = 0; i < outcomes.size(); ++i) {
      std::printf("%-40s %-8s %2d of %2d, worst margin %5.1f %s\n", what.c_str(),
                  lights[i].name.c_str(), outcomes[i].right, outcomes[i].expected,
                  outcomes[i].min_margin, outcomes[i].problems.c_str());
    }
  }

  // Calibrates `palette` through the press; every tag of a sheet in the
  // chosen palette is found with the derived config. Then the same with the
  // default options, and the sheet in `palette` itself.
  static void CalibrateAndDetect(const std::string& palette) {
    std::string out;
    const CommandResult run = Calibrate(palette, &out);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::printf("%s", run.out.c_str());
    const std::string config = out + "/detector.json";
    const std::string chosen = out + "/palette.json";
    ASSERT_TRUE(fs::exists(chosen)) << run.err;

    const PrintedSheet in_chosen = PrintSheet({"--palette-file", chosen}, palette + "-calibrated");
    const std::vector<Outcome> calibrated = Detect(in_chosen, {"--config", config});
    Print("calibrated palette, --config", calibrated);
    ASSERT_EQ(calibrated.size(), Lights().size());
    for (const Outcome& o : calibrated) {
      EXPECT_EQ(o.right, o.expected) << o.problems;
      EXPECT_EQ(o.problems, "");
    }

    // What the calibration changed: the default options on the same photos,
    // and the sheet printed in the palette calibrated.
    Print("calibrated palette, default options", Detect(in_chosen, {}));
    const PrintedSheet in_palette = PrintSheet({"--palette", palette}, palette);
    const std::vector<Outcome> uncalibrated = Detect(in_palette, {});
    Print(palette + " palette, default options", uncalibrated);
    Print(palette + " palette, --config", Detect(in_palette, {"--config", config}));
    // The chosen palette keeps larger margins through the press than the one
    // calibrated, under every light.
    for (size_t i = 0; i < calibrated.size() && i < uncalibrated.size(); ++i)
      EXPECT_GT(calibrated[i].min_margin, uncalibrated[i].min_margin);
  }

  static inline std::string* dir_ = nullptr;
  static inline IccPress* press_ = nullptr;
};

TEST_F(IccCalibrationTest, CalibratedDefaultFindsEveryTagThroughThePress) {
  CalibrateAndDetect("default");
}

// iccv17's b* gaps are thin by design (7.6 and 11.1) and stay thin through
// the press: the calibrated palette must widen them.
TEST_F(IccCalibrationTest, CalibratedIccv17FindsEveryTagThroughThePress) {
  CalibrateAndDetect("iccv17");
}

}  // namespace
}  // namespace chromatag
