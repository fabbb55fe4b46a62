#include "chromatag/detector/corner_bend.h"

#include <cmath>

#include "chromatag/detector/camera.h"

#include "geometry.h"
#include "refine_corners.h"

namespace chromatag {
namespace {

// Points along each side of the square, over the part the detector samples.
constexpr int kSidePoints = 16;

bool Finite(const std::vector<cv::Point2d>& points) {
  for (const cv::Point2d& p : points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  return true;
}

}  // namespace

bool HasDistortion(const CameraIntrinsics& camera) {
  for (double d : camera.distortion)
    if (d != 0.0) return true;
  return false;
}

std::vector<cv::Point2d> CornerBend(const CameraIntrinsics& camera,
                                    const std::vector<cv::Point3d>& ring_corners,
                                    const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  std::vector<cv::Point2d> bend(ring_corners.size(), cv::Point2d(0, 0));
  if (ring_corners.size() < 4) return bend;
  std::vector<cv::Point3d> along;
  for (int s = 0; s < 4; ++s) {
    const cv::Point3d a = ring_corners[s], b = ring_corners[(s + 1) % 4];
    for (int j = 0; j < kSidePoints; ++j) {
      const double t =
          internal::kSideProfilesStart +
          (internal::kSideProfilesEnd - internal::kSideProfilesStart) * j / (kSidePoints - 1);
      along.push_back(a + t * (b - a));
    }
  }
  const std::vector<cv::Point2d> seen = ProjectPoints(camera, along, rvec, tvec);
  const std::vector<cv::Point2d> truth = ProjectPoints(camera, ring_corners, rvec, tvec);
  if (!Finite(seen) || !Finite(truth)) return bend;
  // Each side's line as the detector fits it, and the corners where they
  // meet (corner i on sides i - 1 and i).
  std::array<internal::Line, 4> sides;
  std::vector<cv::Point2d> side;
  std::vector<double> residual, sorted;
  for (int s = 0; s < 4; ++s) {
    side.assign(seen.begin() + s * kSidePoints, seen.begin() + (s + 1) * kSidePoints);
    if (!internal::FitLine(&side, &residual, &sorted, &sides[s])) return bend;
  }
  internal::Quad outer;
  if (!internal::QuadFromSides(sides, &outer)) return bend;
  if (!Finite({outer.begin(), outer.end()})) return bend;
  const std::vector<cv::Point2d> inner =
      PlaceInnerCorners(outer, InnerCornersInSquare(ring_corners));
  if (!Finite(inner)) return bend;
  for (int i = 0; i < 4; ++i) bend[i] = outer[i] - truth[i];
  for (size_t i = 0; i < inner.size(); ++i) bend[4 + i] = inner[i] - truth[4 + i];
  return bend;
}

Detection Straightened(const Detection& detection, const std::vector<cv::Point2d>& bend) {
  Detection out = detection;
  if (bend.size() < 12) return out;
  for (int i = 0; i < 4; ++i) {
    out.corners[i] -= bend[i];
    out.green_corners[i] -= bend[4 + i];
    out.red_corners[i] -= bend[8 + i];
  }
  out.image_from_tag = internal::UnitSquareToQuad(out.corners);
  return out;
}

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

std::vector<cv::Point2d> PlaceInnerCorners(const std::array<cv::Point2d, 4>& outer,
                                           const std::vector<cv::Point2d>& in_square) {
  const cv::Matx33d h = internal::UnitSquareToQuad(outer);
  std::vector<cv::Point2d> placed;
  for (const cv::Point2d& p : in_square) {
    const cv::Vec3d q = h * cv::Vec3d(p.x, p.y, 1.0);
    placed.emplace_back(q[0] / q[2], q[1] / q[2]);
  }
  return placed;
}

}  // namespace chromatag
