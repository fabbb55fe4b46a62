// Small geometry on polygons and quads, on top of OpenCV's (stages.h).
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "stages.h"

namespace chromatag::internal {

double PolygonArea(const std::vector<cv::Point2f>& polygon) {
  return polygon.size() < 3 ? 0.0 : cv::contourArea(polygon);
}

double QuadArea(const Quad& quad) {
  const std::array<cv::Point2f, 4> points = {cv::Point2f(quad[0]), cv::Point2f(quad[1]),
                                             cv::Point2f(quad[2]), cv::Point2f(quad[3])};
  return cv::contourArea(points);
}

cv::Point2f PolygonCentroid(cv::InputArray polygon) {
  const cv::Moments m = cv::moments(polygon);
  if (std::abs(m.m00) < 1e-9) return {NAN, NAN};
  return {static_cast<float>(m.m10 / m.m00), static_cast<float>(m.m01 / m.m00)};
}

bool IntersectLines(cv::Point2d p1, cv::Point2d d1, cv::Point2d p2, cv::Point2d d2,
                    cv::Point2d* at) {
  const double det = d1.x * d2.y - d1.y * d2.x;
  if (std::abs(det) < 1e-12 * (cv::norm(d1) * cv::norm(d2) + 1e-300)) return false;
  const cv::Point2d w = p2 - p1;
  const double s = (w.x * d2.y - w.y * d2.x) / det;
  *at = p1 + s * d1;
  return true;
}

std::vector<cv::Point2f> ClockwiseHull(const std::vector<cv::Point2f>& points) {
  // OpenCV's orientation flag assumes y up; on screen (y down) its
  // counter-clockwise hull runs clockwise.
  std::vector<cv::Point2f> hull;
  if (!points.empty()) cv::convexHull(points, hull, /*clockwise=*/false);
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
  const cv::Point2f src[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  cv::Point2f dst[4];
  for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(quad[i]);
  return cv::Matx33d(cv::getPerspectiveTransform(src, dst));
}

cv::Point2d ApplyHomography(const cv::Matx33d& h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}

}  // namespace chromatag::internal
