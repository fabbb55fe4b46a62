#include "corner_bend.h"

#include <array>
#include <cmath>

#include "chromatag/detector/camera.h"

namespace chromatag::internal {
namespace {

// Points along each side of the square, and the part of the side they
// cover (the detector's profiles run from 12 % to 88 % of the side).
constexpr int kSidePoints = 16;
constexpr double kSideStart = 0.12, kSideEnd = 0.88;

// A total least squares line through `points`: a point on it and its unit
// normal.
void FitLine(const std::vector<cv::Point2d>& points, cv::Point2d* centre, cv::Point2d* normal) {
  cv::Point2d mean(0, 0);
  for (const cv::Point2d& p : points) mean += p / static_cast<double>(points.size());
  double xx = 0, xy = 0, yy = 0;
  for (const cv::Point2d& p : points) {
    const cv::Point2d d = p - mean;
    xx += d.x * d.x;
    xy += d.x * d.y;
    yy += d.y * d.y;
  }
  // The normal is the direction of least spread.
  const double angle = 0.5 * std::atan2(2 * xy, xx - yy);
  *centre = mean;
  *normal = cv::Point2d(-std::sin(angle), std::cos(angle));
}

// Where the lines (a point and a normal each) meet; false when parallel.
bool Meet(const cv::Point2d& pa, const cv::Point2d& na, const cv::Point2d& pb,
          const cv::Point2d& nb, cv::Point2d* at) {
  const double det = na.x * nb.y - na.y * nb.x;
  if (std::abs(det) < 1e-12) return false;
  const double ca = na.dot(pa), cb = nb.dot(pb);
  *at = cv::Point2d((ca * nb.y - cb * na.y) / det, (na.x * cb - nb.x * ca) / det);
  return true;
}

}  // namespace

std::vector<cv::Point2d> InnerCornersInSquare(const std::vector<cv::Point3d>& ring_corners) {
  std::vector<cv::Point2d> in_square;
  if (ring_corners.size() < 4) return in_square;
  const cv::Point3d origin = ring_corners[0];
  const cv::Point3d e1 = ring_corners[1] - origin, e3 = ring_corners[3] - origin;
  for (size_t i = 4; i < ring_corners.size(); ++i) {
    const cv::Point3d d = ring_corners[i] - origin;
    in_square.emplace_back(d.dot(e1) / e1.dot(e1), d.dot(e3) / e3.dot(e3));
  }
  return in_square;
}

std::vector<cv::Point2d> PlaceInnerCorners(const cv::Point2d (&outer)[4],
                                           const std::vector<cv::Point2d>& in_square) {
  // The homography with h33 = 1 taking (0,0), (1,0), (1,1), (0,1) to the
  // four corners: two equations per corner.
  const double unit[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  cv::Matx<double, 8, 8> a = cv::Matx<double, 8, 8>::zeros();
  cv::Vec<double, 8> b;
  for (int i = 0; i < 4; ++i) {
    const double u = unit[i][0], v = unit[i][1], x = outer[i].x, y = outer[i].y;
    const double row_x[8] = {u, v, 1, 0, 0, 0, -u * x, -v * x};
    const double row_y[8] = {0, 0, 0, u, v, 1, -u * y, -v * y};
    for (int k = 0; k < 8; ++k) {
      a(2 * i, k) = row_x[k];
      a(2 * i + 1, k) = row_y[k];
    }
    b[2 * i] = x;
    b[2 * i + 1] = y;
  }
  cv::Vec<double, 8> h;
  std::vector<cv::Point2d> placed;
  if (!cv::solve(a, b, h, cv::DECOMP_LU)) return placed;
  for (const cv::Point2d& p : in_square) {
    const double w = h[6] * p.x + h[7] * p.y + 1;
    placed.emplace_back((h[0] * p.x + h[1] * p.y + h[2]) / w, (h[3] * p.x + h[4] * p.y + h[5]) / w);
  }
  return placed;
}

std::vector<cv::Point2d> CornerBend(const CameraIntrinsics& camera,
                                    const std::vector<cv::Point3d>& ring_corners,
                                    const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  std::vector<cv::Point2d> bend(ring_corners.size(), cv::Point2d(0, 0));
  if (ring_corners.size() < 4) return bend;
  // Each side's points on the board, projected, and the line through them.
  std::vector<cv::Point3d> along;
  for (int s = 0; s < 4; ++s) {
    const cv::Point3d a = ring_corners[s], b = ring_corners[(s + 1) % 4];
    for (int j = 0; j < kSidePoints; ++j) {
      const double t = kSideStart + (kSideEnd - kSideStart) * j / (kSidePoints - 1);
      along.push_back(a + t * (b - a));
    }
  }
  const std::vector<cv::Point2d> seen = ProjectPoints(camera, along, rvec, tvec);
  const std::vector<cv::Point2d> truth = ProjectPoints(camera, ring_corners, rvec, tvec);
  std::array<cv::Point2d, 4> centre, normal;
  for (int s = 0; s < 4; ++s) {
    const std::vector<cv::Point2d> side(seen.begin() + s * kSidePoints,
                                        seen.begin() + (s + 1) * kSidePoints);
    FitLine(side, &centre[s], &normal[s]);
  }
  // Corner i is where side i - 1 (ending at it) meets side i (starting).
  cv::Point2d outer[4];
  for (int i = 0; i < 4; ++i) {
    const int before = (i + 3) % 4;
    if (!Meet(centre[before], normal[before], centre[i], normal[i], &outer[i])) return bend;
    if (!std::isfinite(outer[i].x) || !std::isfinite(outer[i].y)) return bend;
  }
  for (int i = 0; i < 4; ++i) bend[i] = outer[i] - truth[i];
  const std::vector<cv::Point2d> inner =
      PlaceInnerCorners(outer, InnerCornersInSquare(ring_corners));
  for (size_t i = 0; i < inner.size(); ++i) bend[4 + i] = inner[i] - truth[4 + i];
  return bend;
}

}  // namespace chromatag::internal
