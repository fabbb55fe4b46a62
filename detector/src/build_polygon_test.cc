#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "candidate.h"
#include "geometry.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

using testing::RotatedSquare;
using testing::ScanAndBuildPolygon;

// Tag-like colours, as BGR for cv::Mat.
const cv::Scalar kRed(50, 40, 200), kGreen(70, 160, 40), kBlack(20, 20, 20), kWhite(235, 235, 235);

// Concentric squares: red to half-width 12, green to 24, black to 36 (pixel
// centres), white around. Their outlines lie half a pixel further out.
constexpr int kRedHalf = 12, kGreenHalf = 24, kBlackHalf = 36;
constexpr double kBlackOutlineHalf = kBlackHalf + 0.5;

// The pattern turned by `degrees` about `centre`, each square filled through
// its outline (fixed point with 4 fractional bits for sub-pixel corners).
cv::Mat RenderRotatedRings(cv::Size size, cv::Point2d centre, double degrees) {
  constexpr int kShift = 4;
  cv::Mat image(size, CV_8UC3, kWhite);
  auto square = [&](int half, const cv::Scalar& colour) {
    const Quad quad = RotatedSquare(centre, half + 0.5, degrees);
    std::vector<cv::Point> corners;
    for (const cv::Point2d& p : quad)
      corners.emplace_back(cvRound(p.x * (1 << kShift)), cvRound(p.y * (1 << kShift)));
    cv::fillConvexPoly(image, corners, colour, cv::LINE_8, kShift);
  };
  square(kBlackHalf, kBlack);
  square(kGreenHalf, kGreen);
  square(kRedHalf, kRed);
  return image;
}

double DistanceToSegment(cv::Point2d p, cv::Point2d a, cv::Point2d b) {
  const cv::Point2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.dot(ab), 0.0, 1.0);
  return cv::norm(p - (a + t * ab));
}

// Distance from `p` to the outline of `quad`.
double DistanceToOutline(const Quad& quad, cv::Point2d p) {
  double distance = 1e300;
  for (int i = 0; i < 4; ++i)
    distance = std::min(distance, DistanceToSegment(p, quad[i], quad[(i + 1) % 4]));
  return distance;
}

// InitialScan then BuildPolygon from a seed just inside the red's left edge
// on the centre row; the outer hull must cover 95 % of the drawn black
// square and every outer point lie within 1.5 px of its outline.
void ExpectOuterPolygonOnTheBlackSquare(const cv::Mat& image, cv::Point seed, const Quad& black) {
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Candidate candidate;
  ASSERT_TRUE(ScanAndBuildPolygon(view, seed, &candidate));
  const std::vector<cv::Point2f>& outer = candidate.points[kBlackWhite];
  const double drawn_area = QuadArea(black);
  EXPECT_GE(PolygonArea(ClockwiseHull(outer)), 0.95 * drawn_area);
  for (const cv::Point2f& p : outer)
    EXPECT_LT(DistanceToOutline(black, p), 1.5) << "outer point " << p;
}

// On the axis-aligned pattern the outer polygon covers the black square.
TEST(BuildPolygonTest, CoversTheBlackSquare) {
  const int cx = 100, cy = 100;
  cv::Mat image(200, 200, CV_8UC3, kWhite);
  for (auto [half, colour] :
       {std::pair{kBlackHalf, kBlack}, std::pair{kGreenHalf, kGreen}, std::pair{kRedHalf, kRed}}) {
    cv::rectangle(image, {cx - half, cy - half}, {cx + half, cy + half}, colour, cv::FILLED);
  }
  const Quad black = RotatedSquare({cx, cy}, kBlackOutlineHalf, 0.0);
  ASSERT_NEAR(QuadArea(black), 73.0 * 73.0, 1e-6);  // 2 * 36 + 1 pixels a side.
  ExpectOuterPolygonOnTheBlackSquare(image, {cx - kRedHalf + 1, cy}, black);
}

// Turned by 30 degrees, the outer polygon still covers the black square.
TEST(BuildPolygonTest, CoversTheBlackSquareTurnedBy30Degrees) {
  const cv::Point2d centre(100, 100);
  const cv::Mat image = RenderRotatedRings({200, 200}, centre, 30.0);
  // On the centre row the red reaches (12.5 / cos 30) = 14.4 px to the left.
  const cv::Point seed(100 - 13, 100);
  ExpectOuterPolygonOnTheBlackSquare(image, seed, RotatedSquare(centre, kBlackOutlineHalf, 30.0));
}

}  // namespace
}  // namespace chromatag::internal
