#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "candidate.h"
#include "geometry.h"
#include "poly_to_quad.h"
#include "refine_corners.h"
#include "scratch.h"
#include "stage_switches.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

using testing::NearestCorner;
using testing::RotatedSquare;
using testing::ScanAndBuildPolygon;

// Tag-like colours, as BGR.
const cv::Vec3b kRed(50, 40, 200), kGreen(70, 160, 40), kBlack(20, 20, 20), kWhite(235, 235, 235);

// The outlines' half-sides: red 12.5, green 24.5, black 36.5 px (the
// axis-aligned pattern's squares of half-width 12, 24 and 36 pixels).
constexpr double kOutlineHalf[kNumRings] = {12.5, 24.5, 36.5};

// The three rings' squares, antialiased: point-sampled at 8x, then averaged
// down. Coordinates as ImageView::Sample reads them (pixel centres at
// integers), so the high-resolution pixel X has its centre at (X + 0.5) / 8 - 0.5.
cv::Mat RenderRings(cv::Size size, const std::array<Quad, kNumRings>& squares) {
  return testing::RenderQuadsAntialiased(size, {squares.begin(), squares.end()},
                                         {kRed, kGreen, kBlack}, kWhite);
}

// On the antialiased pattern turned by 30 degrees, InitialScan, BuildPolygon
// and PolyToQuad give the outer quad within 0.5 px of its drawn corners and
// the inner ones within a pixel (polygon fits); with their own sub-pixel
// sides, within 0.5 px too.
TEST(PolyToQuadTest, FindsTheDrawnCornersOfEachRing) {
  Scratch scratch;
  const cv::Point2d centre(100.3, 99.6);
  std::array<Quad, kNumRings> truth;
  for (int ring = 0; ring < kNumRings; ++ring)
    truth[ring] = RotatedSquare(centre, kOutlineHalf[ring], 30.0);
  const cv::Mat image = RenderRings({200, 200}, truth);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  // On row 100 the red reaches about 12.5 / cos 30 = 14.4 px left of the centre.
  const cv::Point seed(88, 100);
  Candidate candidate;
  ASSERT_TRUE(ScanAndBuildPolygon(view, seed, &candidate));
  RejectReason why;
  ASSERT_TRUE(
      PolyToQuad(view, StageSwitches{}, &scratch.quad_fit, &scratch.side_fit, &candidate, &why))
      << "PolyToQuad rejected: " << RejectReasonName(why);
  auto expect_near = [&](int ring, double limit, const char* when) {
    const Quad& fitted = candidate.quads[ring];
    // Clockwise like the truth; only the first corner may differ.
    const int shift = NearestCorner(fitted, truth[ring][0]);
    for (int i = 0; i < 4; ++i) {
      const cv::Point2d& p = fitted[(i + shift) % 4];
      EXPECT_LT(cv::norm(p - truth[ring][i]), limit) << when << ", ring " << ring << " corner " << i
                                                     << ": " << p << " drawn at " << truth[ring][i];
    }
  };
  expect_near(kBlackWhite, 0.5, "PolyToQuad");
  expect_near(kGreenBlack, 1.0, "PolyToQuad");
  expect_near(kRedGreen, 1.0, "PolyToQuad");
  ASSERT_TRUE(RefineInnerQuads(view, &scratch.side_fit, &candidate));
  for (int ring = 0; ring < kNumRings; ++ring) expect_near(ring, 0.5, "RefineInnerQuads");
}

}  // namespace
}  // namespace chromatag::internal
