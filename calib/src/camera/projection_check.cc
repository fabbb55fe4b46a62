#include "projection_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/detector/corner_bend.h"

namespace chromatag::internal {
namespace {

// The cell centres of `grid` over `image_size`, row-major.
std::vector<cv::Point2d> CellCentres(cv::Size image_size, cv::Size grid) {
  std::vector<cv::Point2d> centres;
  for (int r = 0; r < grid.height; ++r) {
    for (int c = 0; c < grid.width; ++c) {
      centres.emplace_back((c + 0.5) * image_size.width / grid.width - 0.5,
                           (r + 0.5) * image_size.height / grid.height - 0.5);
    }
  }
  return centres;
}

// The points `camera` sees at `pixels`, `distance` from its centre (NaN
// where the lens model has no ray).
std::vector<cv::Point3d> Unproject(const CameraIntrinsics& camera,
                                   const std::vector<cv::Point2d>& pixels, double distance) {
  std::vector<cv::Point3d> points;
  for (const cv::Point2d& u : UndistortPoints(camera, pixels)) {
    const cv::Vec3d ray((u.x - camera.cx) / camera.fx, (u.y - camera.cy) / camera.fy, 1.0);
    const cv::Vec3d p = ray * (distance / cv::norm(ray));
    points.emplace_back(p[0], p[1], p[2]);
  }
  return points;
}

// How a tag's corners image[start, start + group) move with its four
// measured ones (the first four): the identity for those, the homography's
// derivative (PlaceInnerCorners) for the corners placed from them; 2 group
// x 8.
cv::Mat PlacedCornersJacobian(const std::vector<cv::Point3d>& object,
                              const std::vector<cv::Point2d>& image, size_t start, size_t group) {
  const std::vector<cv::Point3d> ring(object.begin() + start, object.begin() + start + group);
  const std::vector<cv::Point2d> in_square = InnerCornersInSquare(ring);
  cv::Mat jacobian = cv::Mat::zeros(2 * static_cast<int>(group), 8, CV_64F);
  for (int k = 0; k < 8; ++k) jacobian.at<double>(k, k) = 1.0;
  constexpr double kStep = 1e-3;  // Pixels.
  for (int k = 0; k < 8; ++k) {
    std::array<cv::Point2d, 4> plus, minus;
    for (int i = 0; i < 4; ++i) plus[i] = minus[i] = image[start + i];
    (k % 2 ? plus[k / 2].y : plus[k / 2].x) += kStep;
    (k % 2 ? minus[k / 2].y : minus[k / 2].x) -= kStep;
    const std::vector<cv::Point2d> a = PlaceInnerCorners(plus, in_square);
    const std::vector<cv::Point2d> b = PlaceInnerCorners(minus, in_square);
    if (a.size() != in_square.size() || b.size() != in_square.size()) continue;
    for (size_t i = 0; i < in_square.size(); ++i) {
      jacobian.at<double>(8 + 2 * static_cast<int>(i), k) = (a[i].x - b[i].x) / (2 * kStep);
      jacobian.at<double>(9 + 2 * static_cast<int>(i), k) = (a[i].y - b[i].y) / (2 * kStep);
    }
  }
  return jacobian;
}

bool InCentre(const cv::Point2d& p, cv::Size image_size) {
  return p.x >= 0.1 * image_size.width && p.x <= 0.9 * image_size.width &&
         p.y >= 0.1 * image_size.height && p.y <= 0.9 * image_size.height;
}

}  // namespace

void ProjectWithJacobians(const CameraIntrinsics& camera, const std::vector<cv::Point3d>& points,
                          const cv::Vec3d& rvec, const cv::Vec3d& tvec, bool fit_k3,
                          std::vector<cv::Point2d>* projected, cv::Mat* intrinsic_jacobian,
                          cv::Mat* pose_jacobian) {
  const bool fisheye = camera.model == LensModel::kFisheye;
  const cv::Mat k(CameraMatrix(camera));
  const cv::Mat d(camera.distortion, true);
  cv::Mat jacobian;
  if (fisheye) {
    cv::fisheye::projectPoints(points, *projected, rvec, tvec, k, d, 0.0, jacobian);
  } else {
    cv::projectPoints(points, rvec, tvec, k, d, *projected, jacobian);
  }
  jacobian.convertTo(jacobian, CV_64F);
  // cv::fisheye::projectPoints' columns: f(2), c(2), k(4), om(3), T(3),
  // alpha; cv::projectPoints': rvec(3), tvec(3), f(2), c(2), then the
  // distortion (k3 fifth, held when not fitted).
  const int first_intrinsic = fisheye ? 0 : 6;
  const int intrinsics = fisheye ? 8 : (fit_k3 ? 9 : 8);
  const int first_pose = fisheye ? 8 : 0;
  jacobian.colRange(first_intrinsic, first_intrinsic + intrinsics).copyTo(*intrinsic_jacobian);
  if (pose_jacobian) jacobian.colRange(first_pose, first_pose + 6).copyTo(*pose_jacobian);
}

cv::Mat IntrinsicCovariance(const CameraIntrinsics& camera,
                            const std::vector<std::vector<cv::Point3d>>& object,
                            const std::vector<std::vector<cv::Point2d>>& image,
                            const std::vector<cv::Vec3d>& rvecs,
                            const std::vector<cv::Vec3d>& tvecs, bool fit_k3, int corners_per_tag) {
  cv::Mat schur, spread;
  double squares = 0;
  int measured = 0, intrinsics = 0;
  for (size_t v = 0; v < object.size(); ++v) {
    std::vector<cv::Point2d> projected;
    cv::Mat ji, jp;
    ProjectWithJacobians(camera, object[v], rvecs[v], tvecs[v], fit_k3, &projected, &ji, &jp);
    if (schur.empty()) {
      intrinsics = ji.cols;
      schur = cv::Mat::zeros(intrinsics, intrinsics, CV_64F);
      spread = cv::Mat::zeros(intrinsics, intrinsics, CV_64F);
    }
    // How a corner's error moves the intrinsics once the view's pose has
    // taken what it can: J_i - J_p D^-1 B^T, row by row.
    const cv::Mat b = ji.t() * jp;
    const cv::Mat moves = ji - jp * (jp.t() * jp).inv(cv::DECOMP_SVD) * b.t();
    schur += ji.t() * moves;
    const size_t n = object[v].size();
    const size_t group =
        corners_per_tag > 4 && n % corners_per_tag == 0 ? static_cast<size_t>(corners_per_tag) : 1;
    for (size_t start = 0; start < n; start += group) {
      const cv::Mat rows =
          moves.rowRange(2 * static_cast<int>(start), 2 * static_cast<int>(start + group));
      const size_t own = group == 1 ? 1 : 4;  // The corners measured.
      const cv::Mat carried =
          group == 1 ? rows.t()
                     : rows.t() * PlacedCornersJacobian(object[v], image[v], start, group);
      spread += carried * carried.t();
      for (size_t i = start; i < start + own; ++i) {
        const cv::Point2d e = projected[i] - image[v][i];
        squares += e.x * e.x + e.y * e.y;
      }
      measured += 2 * static_cast<int>(own);
    }
  }
  if (schur.empty()) return schur;
  const int parameters = intrinsics + 6 * static_cast<int>(object.size());
  const double variance = squares / std::max(1, measured - parameters);
  const cv::Mat inverse = schur.inv(cv::DECOMP_SVD);
  return inverse * spread * inverse * variance;
}

std::vector<double> UncertaintyMap(const CameraIntrinsics& camera, const cv::Mat& covariance,
                                   bool fit_k3, double distance, cv::Size image_size,
                                   cv::Size grid) {
  const std::vector<cv::Point2d> centres = CellCentres(image_size, grid);
  const std::vector<cv::Point3d> points = Unproject(camera, centres, distance);
  // Each cell's projection moves with the intrinsics as J and with a turn of
  // the camera frame as T (2 x 3). The turn that best undoes a change of the
  // intrinsics over the central cells is -K times it, K = (sum T^T T)^-1
  // sum T^T J; what is left, J - T K, is the projection's own doubt.
  std::vector<cv::Mat> j(points.size()), t(points.size());
  cv::Mat tt = cv::Mat::zeros(3, 3, CV_64F), tj;
  for (size_t i = 0; i < points.size(); ++i) {
    std::vector<cv::Point2d> projected;
    cv::Mat pose;
    ProjectWithJacobians(camera, {points[i]}, cv::Vec3d(), cv::Vec3d(), fit_k3, &projected, &j[i],
                         &pose);
    t[i] = pose.colRange(0, 3).clone();
    if (tj.empty()) tj = cv::Mat::zeros(3, j[i].cols, CV_64F);
    if (!InCentre(centres[i], image_size) || !cv::checkRange(j[i]) || !cv::checkRange(t[i]))
      continue;
    tt += t[i].t() * t[i];
    tj += t[i].t() * j[i];
  }
  const cv::Mat k = tt.inv(cv::DECOMP_SVD) * tj;
  std::vector<double> map;
  for (size_t i = 0; i < points.size(); ++i) {
    const cv::Mat own = j[i] - t[i] * k;
    const cv::Mat c = own * covariance * own.t();
    const double a = c.at<double>(0, 0), b = c.at<double>(0, 1), d = c.at<double>(1, 1);
    const double larger = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
    map.push_back(std::isfinite(larger) ? std::sqrt(std::max(0.0, larger))
                                        : std::numeric_limits<double>::quiet_NaN());
  }
  return map;
}

std::vector<double> CrossValidationMap(const CameraIntrinsics& a, const CameraIntrinsics& b,
                                       double distance, cv::Size image_size, cv::Size grid) {
  const std::vector<cv::Point2d> centres = CellCentres(image_size, grid);
  const std::vector<cv::Point3d> seen_a = Unproject(a, centres, distance);
  const std::vector<cv::Point3d> seen_b = Unproject(b, centres, distance);
  // The rotation taking a's rays onto b's (Kabsch), over the central cells.
  cv::Matx33d h = cv::Matx33d::zeros();
  for (size_t i = 0; i < centres.size(); ++i) {
    if (!InCentre(centres[i], image_size)) continue;
    const cv::Vec3d ra(seen_a[i]), rb(seen_b[i]);
    if (!std::isfinite(ra.dot(ra)) || !std::isfinite(rb.dot(rb))) continue;
    h += (ra / cv::norm(ra)) * (rb / cv::norm(rb)).t();
  }
  cv::Mat w, u, vt;
  cv::SVD::compute(cv::Mat(h), w, u, vt);
  cv::Mat flip = cv::Mat::eye(3, 3, CV_64F);
  flip.at<double>(2, 2) = cv::determinant(vt.t() * u.t()) < 0 ? -1 : 1;
  const cv::Matx33d r(cv::Mat(vt.t() * flip * u.t()));
  std::vector<cv::Point3d> turned;
  for (const cv::Point3d& p : seen_a) {
    const cv::Vec3d q = r * cv::Vec3d(p.x, p.y, p.z);
    turned.emplace_back(q[0], q[1], q[2]);
  }
  const std::vector<cv::Point2d> projected = ProjectPoints(b, turned, cv::Vec3d(), cv::Vec3d());
  std::vector<double> map;
  for (size_t i = 0; i < centres.size(); ++i) map.push_back(cv::norm(projected[i] - centres[i]));
  return map;
}

void CentralFigures(const std::vector<double>& map, cv::Size image_size, cv::Size grid,
                    double* median, double* worst) {
  const std::vector<cv::Point2d> centres = CellCentres(image_size, grid);
  std::vector<double> central;
  bool unknown = false;
  for (size_t i = 0; i < map.size() && i < centres.size(); ++i) {
    if (!InCentre(centres[i], image_size)) continue;
    if (std::isfinite(map[i])) {
      central.push_back(map[i]);
    } else {
      unknown = true;  // A cell the model has no ray for: nothing is known there.
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (central.empty()) {
    *median = *worst = nan;
    return;
  }
  std::sort(central.begin(), central.end());
  *median = central[central.size() / 2];
  *worst = unknown ? std::numeric_limits<double>::infinity() : central.back();
}

bool BeyondNoise(const std::vector<double>& difference, const std::vector<double>& expected,
                 cv::Size image_size, cv::Size grid, double limit, double sigmas) {
  const std::vector<cv::Point2d> centres = CellCentres(image_size, grid);
  for (size_t i = 0; i < centres.size() && i < difference.size() && i < expected.size(); ++i) {
    if (InCentre(centres[i], image_size) && difference[i] > limit &&
        difference[i] > sigmas * expected[i])
      return true;
  }
  return false;
}

}  // namespace chromatag::internal
