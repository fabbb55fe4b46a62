// Printing through a real press profile (issue 13): Ghostscript's SWOP press
// (default_cmyk.icc) applied with LittleCMS, what it does to the palettes,
// and the geometry of a printed and scanned page.
#include "icc_press.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "calib_sim.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag {
namespace {

using testing::IccPress;
using testing::PrintGeometry;
using testing::ScanPixelOfPagePoint;
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

}  // namespace
}  // namespace chromatag
