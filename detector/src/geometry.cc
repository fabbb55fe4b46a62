#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "stages.h"

namespace chromatag::internal {

double PolygonArea(const std::vector<cv::Point2f>& polygon) {
  double twice = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const cv::Point2f& p = polygon[i];
    const cv::Point2f& q = polygon[(i + 1) % polygon.size()];
    twice += static_cast<double>(p.x) * q.y - static_cast<double>(q.x) * p.y;
  }
  return 0.5 * std::abs(twice);
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
  std::vector<cv::Point2f> hull;
  cv::convexHull(points, hull);
  double twice = 0.0;
  for (size_t i = 0; i < hull.size(); ++i) {
    const auto& p = hull[i];
    const auto& q = hull[(i + 1) % hull.size()];
    twice += static_cast<double>(p.x) * q.y - static_cast<double>(q.x) * p.y;
  }
  if (twice < 0) std::reverse(hull.begin(), hull.end());
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

}  // namespace chromatag::internal
