#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "geometry.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

using testing::RotatedSquare;

// Cross product of the edges a -> b and b -> c: positive for a clockwise turn
// on screen (y down).
double Turn(cv::Point2f a, cv::Point2f b, cv::Point2f c) {
  const cv::Point2d u = b - a, v = c - b;
  return u.x * v.y - u.y * v.x;
}

void ExpectClockwiseConvex(const std::vector<cv::Point2f>& hull) {
  const size_t n = hull.size();
  for (size_t i = 0; i < n; ++i) {
    EXPECT_GT(Turn(hull[i], hull[(i + 1) % n], hull[(i + 2) % n]), 0.0) << "at vertex " << i;
  }
}

bool SamePointSets(std::vector<cv::Point2f> a, std::vector<cv::Point2f> b) {
  auto less = [](cv::Point2f p, cv::Point2f q) { return p.x < q.x || (p.x == q.x && p.y < q.y); };
  std::sort(a.begin(), a.end(), less);
  std::sort(b.begin(), b.end(), less);
  return a == b;
}

// The hull of a square's corners, its edge midpoints (collinear), repeated
// corners and interior points is the four corners, clockwise on screen.
TEST(GeometryTest, HullKeepsOnlyTheCornersClockwise) {
  const std::vector<cv::Point2f> corners = {{10, 10}, {50, 10}, {50, 40}, {10, 40}};
  std::vector<cv::Point2f> points = corners;
  points.insert(points.end(), {{30, 10}, {50, 25}, {30, 40}, {10, 25}, {40, 10}});  // On sides.
  points.insert(points.end(), {{10, 10}, {50, 40}, {50, 40}});                      // Repeats.
  points.insert(points.end(), {{20, 20}, {30, 25}, {49, 39}, {11, 11}});            // Inside.
  const std::vector<cv::Point2f> hull = ClockwiseHull(points);
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_TRUE(SamePointSets(hull, corners));
  ExpectClockwiseConvex(hull);
}

// On random clouds the hull has the same vertices as OpenCV's, turning
// clockwise at each, and the reused-output overload agrees.
TEST(GeometryTest, HullMatchesOpenCvOnRandomClouds) {
  cv::RNG rng(7);
  std::vector<cv::Point2f> reused = {{1, 2}, {3, 4}};  // Stale content must go.
  std::vector<cv::Point2f> sorted = {{5, 6}};          // Likewise.
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<cv::Point2f> points(3 + trial);
    for (auto& p : points) p = {rng.uniform(-100.f, 100.f), rng.uniform(-50.f, 80.f)};
    std::vector<cv::Point2f> expected;
    cv::convexHull(points, expected);
    const std::vector<cv::Point2f> hull = ClockwiseHull(points);
    EXPECT_TRUE(SamePointSets(hull, expected)) << "trial " << trial;
    ExpectClockwiseConvex(hull);
    ClockwiseHull(points, &sorted, &reused);
    EXPECT_EQ(reused, hull);
  }
}

// Fewer than three points, or all on one line, give the distinct extremes.
TEST(GeometryTest, HullOfDegenerateInputs) {
  EXPECT_TRUE(ClockwiseHull({}).empty());
  EXPECT_EQ(ClockwiseHull({{3, 4}}), (std::vector<cv::Point2f>{{3, 4}}));
  EXPECT_EQ(ClockwiseHull({{3, 4}, {3, 4}}), (std::vector<cv::Point2f>{{3, 4}}));
  EXPECT_TRUE(SamePointSets(ClockwiseHull({{5, 1}, {3, 4}}), {{3, 4}, {5, 1}}));
  EXPECT_TRUE(
      SamePointSets(ClockwiseHull({{2, 2}, {0, 0}, {4, 4}, {1, 1}, {3, 3}}), {{0, 0}, {4, 4}}));
}

// n >= 3 copies of one point are as degenerate as two: one point.
TEST(GeometryTest, HullOfRepeatedSinglePoint) {
  EXPECT_EQ(ClockwiseHull({{3, 4}, {3, 4}, {3, 4}}), (std::vector<cv::Point2f>{{3, 4}}));
}

// Areas of a rectangle, a triangle and a rotated square, in either
// orientation; fewer than three points have none.
TEST(GeometryTest, AreasOfKnownShapes) {
  std::vector<cv::Point2f> rectangle = {{2, 3}, {32, 3}, {32, 23}, {2, 23}};
  EXPECT_DOUBLE_EQ(PolygonArea(rectangle), 30.0 * 20.0);
  std::reverse(rectangle.begin(), rectangle.end());
  EXPECT_DOUBLE_EQ(PolygonArea(rectangle), 30.0 * 20.0);
  EXPECT_DOUBLE_EQ(PolygonArea({{0, 0}, {12, 0}, {5, 7}}), 0.5 * 12 * 7);
  EXPECT_DOUBLE_EQ(PolygonArea({{0, 0}, {12, 0}}), 0.0);

  Quad square = RotatedSquare({100.5, 40.25}, 8.5, 33.0);
  EXPECT_NEAR(QuadArea(square), 17.0 * 17.0, 1e-9);
  std::reverse(square.begin(), square.end());
  EXPECT_NEAR(QuadArea(square), 17.0 * 17.0, 1e-9);
  // A trapezoid: mean of the parallel sides times the height.
  EXPECT_DOUBLE_EQ(QuadArea({{{0, 0}, {10, 0}, {8, 5}, {4, 5}}}), 0.5 * (10 + 4) * 5);
}

// The centroid of an L (two rectangles, eight vertices with two collinear
// ones) is the area-weighted mean of the rectangles' centres, in either
// orientation.
TEST(GeometryTest, CentroidOfAnLByDecomposition) {
  // Bar [0, 40] x [0, 10] and leg [0, 10] x [10, 40].
  std::array<cv::Point2f, 8> l_shape = {
      {{0, 0}, {20, 0}, {40, 0}, {40, 10}, {10, 10}, {10, 40}, {0, 40}, {0, 20}}};
  const double bar = 40 * 10, leg = 10 * 30;
  const cv::Point2d expected = (bar * cv::Point2d(20, 5) + leg * cv::Point2d(5, 25)) / (bar + leg);
  cv::Point2f centroid = PolygonCentroid(l_shape);
  EXPECT_NEAR(centroid.x, expected.x, 1e-4);
  EXPECT_NEAR(centroid.y, expected.y, 1e-4);
  std::reverse(l_shape.begin(), l_shape.end());
  centroid = PolygonCentroid(l_shape);
  EXPECT_NEAR(centroid.x, expected.x, 1e-4);
  EXPECT_NEAR(centroid.y, expected.y, 1e-4);
}

// Far from the origin a small square's centroid is still its centre, to
// float precision there.
TEST(GeometryTest, CentroidFarFromTheOrigin) {
  const float cx = 1000.5f, cy = 2000.25f, h = 1.5f;
  const std::array<cv::Point2f, 4> square = {
      {{cx - h, cy - h}, {cx + h, cy - h}, {cx + h, cy + h}, {cx - h, cy + h}}};
  const cv::Point2f centroid = PolygonCentroid(square);
  EXPECT_NEAR(centroid.x, cx, 1e-3);
  EXPECT_NEAR(centroid.y, cy, 1e-3);
}

// A polygon without area has no centroid.
TEST(GeometryTest, CentroidOfCollinearPointsIsNan) {
  const std::array<cv::Point2f, 4> line = {{{1, 1}, {2, 2}, {5, 5}, {3, 3}}};
  const cv::Point2f centroid = PolygonCentroid(line);
  EXPECT_TRUE(std::isnan(centroid.x));
  EXPECT_TRUE(std::isnan(centroid.y));
  const std::array<cv::Point2f, 3> same = {{{7, 7}, {7, 7}, {7, 7}}};
  EXPECT_TRUE(std::isnan(PolygonCentroid(same).x));
}

// Two lines meet where both parametrisations agree; parallel lines do not.
TEST(GeometryTest, IntersectLines) {
  cv::Point2d at;
  // y = 2x + 1 and y = -x + 7 meet at (2, 5).
  ASSERT_TRUE(IntersectLines({0, 1}, {1, 2}, {7, 0}, {-3, 3}, &at));
  EXPECT_NEAR(at.x, 2.0, 1e-12);
  EXPECT_NEAR(at.y, 5.0, 1e-12);
  const cv::Point2d untouched(-1, -1);
  at = untouched;
  EXPECT_FALSE(IntersectLines({0, 0}, {1, 2}, {5, 0}, {-2, -4}, &at));
  EXPECT_EQ(at, untouched);
}

// Convex clockwise quads pass; the same reversed, or a dart, do not.
TEST(GeometryTest, IsConvexClockwise) {
  Quad square = RotatedSquare({10, 10}, 3, 20);
  EXPECT_TRUE(IsConvexClockwise(square));
  std::reverse(square.begin(), square.end());
  EXPECT_FALSE(IsConvexClockwise(square));
  EXPECT_FALSE(IsConvexClockwise({{{0, 0}, {10, 0}, {3, 3}, {0, 10}}}));
}

// The unit square's corners land on the quad's corners, and its centre on
// the crossing of the quad's diagonals (a homography keeps lines).
TEST(GeometryTest, UnitSquareToQuadMapsCornersAndCentre) {
  const Quad quad = {{{12.5, 8}, {70, 15.25}, {60, 66}, {5, 50}}};
  const cv::Matx33d h = UnitSquareToQuad(quad);
  const double unit[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d p = ApplyHomography(h, unit[i][0], unit[i][1]);
    EXPECT_NEAR(p.x, quad[i].x, 1e-4) << "corner " << i;
    EXPECT_NEAR(p.y, quad[i].y, 1e-4) << "corner " << i;
  }
  cv::Point2d crossing;
  ASSERT_TRUE(IntersectLines(quad[0], quad[2] - quad[0], quad[1], quad[3] - quad[1], &crossing));
  const cv::Point2d centre = ApplyHomography(h, 0.5, 0.5);
  EXPECT_NEAR(centre.x, crossing.x, 1e-4);
  EXPECT_NEAR(centre.y, crossing.y, 1e-4);
}

// The closed form gives OpenCV's homography (normalised the same way), for
// a parallelogram (no projective part) as for perspective views.
TEST(GeometryTest, UnitSquareToQuadMatchesGetPerspectiveTransform) {
  const Quad quads[] = {{{{12.5, 8}, {70, 15.25}, {60, 66}, {5, 50}}},
                        {{{10, 10}, {50, 20}, {60, 60}, {20, 50}}},  // Parallelogram.
                        {{{300, 200}, {420, 190}, {400, 260}, {310, 250}}},
                        {{{-5, 3}, {2, -4}, {9, 3}, {2, 10}}}};
  const cv::Point2f unit[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const Quad& quad : quads) {
    cv::Point2f dst[4];
    for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(quad[i]);
    const cv::Matx33d expected(cv::getPerspectiveTransform(unit, dst));
    const cv::Matx33d h = UnitSquareToQuad(quad);
    for (int k = 0; k < 9; ++k)
      EXPECT_NEAR(h.val[k], expected.val[k], 1e-6 * (1 + std::abs(expected.val[k])));
  }
  // Three corners in a line: no homography (all zeros, as OpenCV's).
  EXPECT_EQ(UnitSquareToQuad({{{0, 0}, {1, 0}, {2, 0}, {0, 1}}}), cv::Matx33d::zeros());
}

}  // namespace
}  // namespace chromatag::internal

namespace chromatag::internal {
namespace {

// The closed form agrees with the angle formula 0.5 atan2(2 sxy, sxx - syy)
// on random scatters, points into x >= 0, and falls back to (1, 0).
TEST(GeometryTest, MajorAxisMatchesTheAngleFormula) {
  cv::RNG rng(11);
  for (int i = 0; i < 2000; ++i) {
    const double sxx = rng.uniform(0.0, 50.0), syy = rng.uniform(0.0, 50.0);
    const double limit = std::sqrt(sxx * syy);  // A scatter matrix is positive semidefinite.
    const double sxy = rng.uniform(-limit, limit);
    const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
    const cv::Point2d expected(std::cos(angle), std::sin(angle));
    const cv::Point2d axis = MajorAxis(sxx, sxy, syy);
    EXPECT_NEAR(cv::norm(axis), 1.0, 1e-12);
    EXPECT_GE(axis.x, 0.0);
    // Up to the sign when the axis is vertical, where both formulas may
    // pick either end.
    EXPECT_LT(std::min(cv::norm(axis - expected), cv::norm(axis + expected)), 1e-9)
        << sxx << " " << sxy << " " << syy;
  }
  EXPECT_EQ(MajorAxis(0, 0, 0), cv::Point2d(1, 0));
  EXPECT_EQ(MajorAxis(0, 0, 4), cv::Point2d(0, 1));
  EXPECT_EQ(MajorAxis(4, 0, 0), cv::Point2d(1, 0));
}

}  // namespace
}  // namespace chromatag::internal
