#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "candidate.h"
#include "scan_rings.h"
#include "scratch.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

// Tag-like colours, as BGR for cv::Mat.
const cv::Scalar kRed(50, 40, 200), kGreen(70, 160, 40), kBlack(20, 20, 20), kWhite(235, 235, 235);

// Concentric filled squares about (cx, cy): pixels within half-width 20 are
// red, 30 green, 40 black, the rest white. A missing colour is skipped.
constexpr int kRedHalf = 20, kGreenHalf = 30, kBlackHalf = 40;

cv::Mat RenderRings(cv::Size size, int cx, int cy, bool with_green = true) {
  // Without the green ring the red lies straight on white (no black ring).
  return testing::RenderRings(size, cx, cy, {kRedHalf, kGreenHalf, kBlackHalf}, with_green,
                              with_green);
}

float ReferenceRed() { return ColorTable::Get().A(200, 40, 50); }

// A hard edge between the last pixel of one ring (half-width `half` from the
// centre) and the first of the next lies half a pixel past it.
constexpr double EdgeOffset(int half) { return half + 0.5; }

// Scanning from the centre along each axis finds the three drawn borders, in
// order, within half a pixel (the gap between the two pixels either side).
TEST(ScanRingsTest, FindsTheThreeBordersAlongTheAxes) {
  Scratch scratch;
  const int cx = 100, cy = 90;
  const cv::Mat image = RenderRings({200, 180}, cx, cy);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const cv::Point2f directions[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  const int halves[kNumRings] = {kRedHalf, kGreenHalf, kBlackHalf};
  for (const cv::Point2f& d : directions) {
    RingHits hits;
    ASSERT_TRUE(ScanRings(view, DetectorOptions{}, cv::Point2f(cx, cy), d, ReferenceRed(),
                          &scratch.ring_scan, &hits))
        << "direction " << d;
    for (int ring = 0; ring < kNumRings; ++ring) {
      const cv::Point2f expected = cv::Point2f(cx, cy) + EdgeOffset(halves[ring]) * d;
      EXPECT_NEAR(hits.border[ring].x, expected.x, 0.5) << "direction " << d << " ring " << ring;
      EXPECT_NEAR(hits.border[ring].y, expected.y, 0.5) << "direction " << d << " ring " << ring;
    }
  }
}

// Diagonal scans, one nearest pixel per unit step, land within a pixel of
// the square borders (Chebyshev distance from the centre).
TEST(ScanRingsTest, FindsTheBordersAlongDiagonals) {
  Scratch scratch;
  const int cx = 100, cy = 100;
  const cv::Mat image = RenderRings({200, 200}, cx, cy);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const float s = std::sqrt(0.5f);
  const int halves[kNumRings] = {kRedHalf, kGreenHalf, kBlackHalf};
  for (const cv::Point2f& d : {cv::Point2f(s, s), cv::Point2f(-s, s), cv::Point2f(-s, -s)}) {
    RingHits hits;
    ASSERT_TRUE(ScanRings(view, DetectorOptions{}, cv::Point2f(cx, cy), d, ReferenceRed(),
                          &scratch.ring_scan, &hits));
    for (int ring = 0; ring < kNumRings; ++ring) {
      const cv::Point2f offset = hits.border[ring] - cv::Point2f(cx, cy);
      EXPECT_NEAR(std::abs(offset.x), EdgeOffset(halves[ring]), 1.0) << "ring " << ring;
      EXPECT_NEAR(std::abs(offset.y), EdgeOffset(halves[ring]), 1.0) << "ring " << ring;
    }
  }
}

// Red straight on white is no tag: there is no green ring to scan through.
TEST(ScanRingsTest, FailsWithoutTheGreenRing) {
  Scratch scratch;
  const cv::Mat image = RenderRings({200, 200}, 100, 100, /*with_green=*/false);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  for (const cv::Point2f& d : {cv::Point2f(1, 0), cv::Point2f(0, -1)}) {
    RingHits hits;
    EXPECT_FALSE(ScanRings(view, DetectorOptions{}, {100, 100}, d, ReferenceRed(),
                           &scratch.ring_scan, &hits));
  }
}

// A tag cut off by the frame edge inside its black ring fails in that
// direction only.
TEST(ScanRingsTest, FailsWhenTheScanLeavesTheFrame) {
  Scratch scratch;
  const int cx = 100, cy = 100;
  // The right edge (x = 134) lies inside the black ring (x up to 140).
  const cv::Mat image = RenderRings({cx + kGreenHalf + 5, 200}, cx, cy);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  RingHits hits;
  EXPECT_FALSE(ScanRings(view, DetectorOptions{}, cv::Point2f(cx, cy), {1, 0}, ReferenceRed(),
                         &scratch.ring_scan, &hits));
  EXPECT_TRUE(ScanRings(view, DetectorOptions{}, cv::Point2f(cx, cy), {-1, 0}, ReferenceRed(),
                        &scratch.ring_scan, &hits));
}

}  // namespace
}  // namespace chromatag::internal
