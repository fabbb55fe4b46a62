// Small geometry on polygons and quads (geometry.h), the detector's one copy.
// Written out rather than called through OpenCV: the polygons have a few
// dozen points, and cv::convexHull, cv::contourArea and cv::moments cost more
// in their InputArray wrapping and buffers than in the arithmetic
// (BuildPolygon takes a hull and an area on every scan, InitialScan a
// centroid on every pass). Measured with detector_bench against the same
// functions through OpenCV: one-tag frame 86.5 -> 82.5 us, camera frames
// with tags 161 -> 155 us. geometry_test checks the hull against
// cv::convexHull.
#include "geometry.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace chromatag::internal {

namespace {

// Twice the signed area (shoelace) of the polygon points[0 .. n - 1].
template <typename Point>
double TwiceSignedArea(const Point* points, size_t n) {
  double sum = 0.0;
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    sum += static_cast<double>(points[j].x) * points[i].y -
           static_cast<double>(points[i].x) * points[j].y;
  }
  return sum;
}

}  // namespace

double PolygonArea(const std::vector<cv::Point2f>& polygon) {
  return polygon.size() < 3 ? 0.0 : 0.5 * std::abs(TwiceSignedArea(polygon.data(), polygon.size()));
}

double QuadArea(const Quad& quad) { return 0.5 * std::abs(TwiceSignedArea(quad.data(), 4)); }

cv::Point2f PolygonCentroid(const cv::Point2f* polygon, size_t n) {
  // Area centroid by Green's theorem, about the first point (better
  // conditioned far from the origin).
  if (n < 3) return {NAN, NAN};
  const double ox = polygon[0].x, oy = polygon[0].y;
  double a2 = 0.0, cx = 0.0, cy = 0.0;
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xj = polygon[j].x - ox, yj = polygon[j].y - oy;
    const double xi = polygon[i].x - ox, yi = polygon[i].y - oy;
    const double cross = xj * yi - xi * yj;
    a2 += cross;
    cx += (xj + xi) * cross;
    cy += (yj + yi) * cross;
  }
  if (std::abs(a2) < 2e-9) return {NAN, NAN};
  return {static_cast<float>(ox + cx / (3.0 * a2)), static_cast<float>(oy + cy / (3.0 * a2))};
}

void ClockwiseHull(const std::vector<cv::Point2f>& points, std::vector<cv::Point2f>* sorted_buffer,
                   std::vector<cv::Point2f>* hull) {
  // Andrew's monotone chain. A turn with a positive cross product is
  // clockwise on screen (y down); collinear and repeated points are dropped.
  std::vector<cv::Point2f>& sorted = *sorted_buffer;
  sorted.assign(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(), [](const cv::Point2f& a, const cv::Point2f& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  hull->clear();
  const size_t n = sorted.size();
  if (n < 3) {
    if (n > 0) hull->push_back(sorted.front());
    if (n > 1) hull->push_back(sorted.back());
    return;
  }
  hull->resize(2 * n);
  auto turn = [](const cv::Point2f& o, const cv::Point2f& a, const cv::Point2f& b) {
    return (static_cast<double>(a.x) - o.x) * (static_cast<double>(b.y) - o.y) -
           (static_cast<double>(a.y) - o.y) * (static_cast<double>(b.x) - o.x);
  };
  size_t k = 0;
  auto& h = *hull;
  for (size_t i = 0; i < n; ++i) {  // Lower chain on screen: left to right along the top.
    while (k >= 2 && turn(h[k - 2], h[k - 1], sorted[i]) <= 0) --k;
    h[k++] = sorted[i];
  }
  for (size_t i = n - 1, lower = k + 1; i-- > 0;) {  // And back along the bottom.
    while (k >= lower && turn(h[k - 2], h[k - 1], sorted[i]) <= 0) --k;
    h[k++] = sorted[i];
  }
  hull->resize(k > 1 ? k - 1 : k);  // The last point repeats the first.
}

std::vector<cv::Point2f> ClockwiseHull(const std::vector<cv::Point2f>& points) {
  std::vector<cv::Point2f> sorted, hull;
  ClockwiseHull(points, &sorted, &hull);
  return hull;
}

bool IsConvexClockwise(const Quad& quad) {
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d a = quad[(i + 1) % 4] - quad[i];
    const cv::Point2d b = quad[(i + 2) % 4] - quad[(i + 1) % 4];
    // Clockwise on screen (y down) turns with a positive cross product.
    if (a.x * b.y - a.y * b.x <= 0.0) return false;
  }
  return true;
}

cv::Matx33d UnitSquareToQuad(const Quad& quad) {
  // Closed form (Heckbert, "Fundamentals of Texture Mapping and Image
  // Warping", 1989): the projective part from how far the quad is from a
  // parallelogram, then the rest; H(2, 2) = 1 as cv::getPerspectiveTransform
  // gives, without its 8 x 8 solve and buffers (Decode takes two a tag).
  const double x0 = quad[0].x, y0 = quad[0].y, x1 = quad[1].x, y1 = quad[1].y;
  const double x2 = quad[2].x, y2 = quad[2].y, x3 = quad[3].x, y3 = quad[3].y;
  const double dx1 = x1 - x2, dx2 = x3 - x2, dx3 = x0 - x1 + x2 - x3;
  const double dy1 = y1 - y2, dy2 = y3 - y2, dy3 = y0 - y1 + y2 - y3;
  // No homography when three corners lie in a line (as OpenCV's solve).
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d a = quad[(i + 1) % 4] - quad[i], b = quad[(i + 2) % 4] - quad[i];
    if (!(std::abs(a.x * b.y - a.y * b.x) > 0.0)) return cv::Matx33d::zeros();
  }
  const double det = dx1 * dy2 - dx2 * dy1;
  const double g = (dx3 * dy2 - dx2 * dy3) / det;
  const double h = (dx1 * dy3 - dx3 * dy1) / det;
  return cv::Matx33d(x1 - x0 + g * x1, x3 - x0 + h * x3, x0,  //
                     y1 - y0 + g * y1, y3 - y0 + h * y3, y0,  //
                     g, h, 1.0);
}

cv::Point2d MajorAxis(double sxx, double sxy, double syy) {
  const double half_difference = 0.5 * (sxx - syy);
  const double largest =
      0.5 * (sxx + syy) + std::sqrt(half_difference * half_difference + sxy * sxy);
  // (largest - syy, sxy) and (sxy, largest - sxx) both lie along the axis;
  // the longer is the better conditioned.
  cv::Point2d axis(largest - syy, sxy);
  const cv::Point2d other(sxy, largest - sxx);
  if (other.dot(other) > axis.dot(axis)) axis = other;
  const double length = std::sqrt(axis.dot(axis));
  if (!(length > 0)) return {1, 0};
  axis *= 1.0 / length;
  if (axis.x < 0 || (axis.x == 0 && axis.y < 0)) axis = -axis;
  return axis;
}

}  // namespace chromatag::internal
