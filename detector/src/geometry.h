// Geometry helpers (geometry.cc): the quad the stages pass around, and small
// geometry on polygons and quads. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_GEOMETRY_H_
#define CHROMATAG_DETECTOR_SRC_GEOMETRY_H_

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

namespace chromatag::internal {

using Quad = std::array<cv::Point2d, 4>;  // Clockwise on screen (x right, y down).

// Unsigned areas in square pixels.
double PolygonArea(const std::vector<cv::Point2f>& polygon);
double QuadArea(const Quad& quad);
// The side of the square of the same area as `quad`.
inline double QuadSide(const Quad& quad) { return std::sqrt(QuadArea(quad)); }
// Area centroid of a simple polygon; NaN if degenerate.
cv::Point2f PolygonCentroid(const cv::Point2f* polygon, size_t n);
template <size_t N>
cv::Point2f PolygonCentroid(const std::array<cv::Point2f, N>& polygon) {
  return PolygonCentroid(polygon.data(), N);
}
// Where the lines p1 + s d1 and p2 + t d2 meet; false if they are parallel
// within 1e-12 of the directions' lengths. Inline: BuildPolygon calls it for
// every hull edge on every scan, and across a call the points' coordinates
// went through memory (stalls that cost more than the arithmetic).
inline bool IntersectLines(cv::Point2d p1, cv::Point2d d1, cv::Point2d p2, cv::Point2d d2,
                           cv::Point2d* at) {
  const double det = d1.x * d2.y - d1.y * d2.x;
  // Parallel within 1e-12 of the directions' lengths. The L1 lengths bound
  // the L2 ones from above, so a determinant past their bound is past this
  // one too: the square roots are taken only near the limit (BuildPolygon
  // calls this for every hull edge on every scan).
  const double l1 = (std::abs(d1.x) + std::abs(d1.y)) * (std::abs(d2.x) + std::abs(d2.y));
  if (!(std::abs(det) >= 1e-12 * (l1 + 1e-300)) &&
      std::abs(det) < 1e-12 * (cv::norm(d1) * cv::norm(d2) + 1e-300)) {
    return false;
  }
  const cv::Point2d w = p2 - p1;
  const double s = (w.x * d2.y - w.y * d2.x) / det;
  *at = p1 + s * d1;
  return true;
}
bool IsConvexClockwise(const Quad& quad);
// A line through `point` along `direction` (unit where Distance is used).
struct Line {
  cv::Point2d point;
  cv::Point2d direction;
  double Distance(const cv::Point2d& p) const {
    const cv::Point2d d = p - point;
    return std::abs(d.x * direction.y - d.y * direction.x);
  }
};
// The quad whose side i is sides[i]: corner i where side i - 1 meets side i.
// False if two neighbouring sides are parallel.
inline bool QuadFromSides(const std::array<Line, 4>& sides, Quad* quad) {
  for (int i = 0; i < 4; ++i) {
    const Line& a = sides[(i + 3) % 4];
    const Line& b = sides[i];
    if (!IntersectLines(a.point, a.direction, b.point, b.direction, &(*quad)[i])) return false;
  }
  return true;
}
// The unit direction of the major axis of a scatter with second moments
// sxx, sxy, syy about its mean (the total least squares line's direction),
// x >= 0 (y > 0 when x = 0); in closed form, no trigonometry. (1, 0) for a
// scatter with no spread.
cv::Point2d MajorAxis(double sxx, double sxy, double syy);
// The convex hull of `points`, clockwise on screen (y down), without
// collinear points; into *hull (reused, with *sorted for the points sorted)
// or returned.
void ClockwiseHull(const std::vector<cv::Point2f>& points, std::vector<cv::Point2f>* sorted,
                   std::vector<cv::Point2f>* hull);
std::vector<cv::Point2f> ClockwiseHull(const std::vector<cv::Point2f>& points);
// The homography from the unit square ((0,0), (1,0), (1,1), (0,1)) to `quad`,
// and a point through a homography (inline, as IntersectLines: Decode maps
// three points a cell).
cv::Matx33d UnitSquareToQuad(const Quad& quad);
inline cv::Point2d ApplyHomography(const cv::Matx33d& h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}
// The square from (inset, inset) to (1 - inset, 1 - inset) of the unit
// square through `h`, clockwise from its top-left: with `h` a tag's
// UnitSquareToQuad, the border `inset` * cells cells inside its black square.
inline Quad InsetSquare(const cv::Matx33d& h, double inset) {
  const double lo = inset, hi = 1 - inset;
  return {ApplyHomography(h, lo, lo), ApplyHomography(h, hi, lo), ApplyHomography(h, hi, hi),
          ApplyHomography(h, lo, hi)};
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_GEOMETRY_H_
