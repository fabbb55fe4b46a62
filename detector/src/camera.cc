#include "chromatag/detector/camera.h"

#include <cmath>

#include <opencv2/calib3d.hpp>

namespace chromatag {
namespace {

// The distortion as OpenCV takes it; none is zeros for the fisheye model,
// whose functions need all four.
cv::Mat Coefficients(const CameraIntrinsics& camera) {
  if (camera.distortion.empty() && camera.model == LensModel::kFisheye)
    return cv::Mat::zeros(4, 1, CV_64F);
  return cv::Mat(camera.distortion, /*copyData=*/true);
}

}  // namespace

cv::Matx33d CameraMatrix(const CameraIntrinsics& camera) {
  return cv::Matx33d(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
}

std::vector<cv::Point2d> ProjectPoints(const CameraIntrinsics& camera,
                                       const std::vector<cv::Point3d>& points,
                                       const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  std::vector<cv::Point2d> image;
  if (points.empty()) return image;
  const cv::Mat k(CameraMatrix(camera));
  const cv::Mat d = Coefficients(camera);
  if (camera.model == LensModel::kFisheye) {
    cv::fisheye::projectPoints(points, image, rvec, tvec, k, d);
  } else {
    cv::projectPoints(points, rvec, tvec, k, d, image);
  }
  return image;
}

std::vector<cv::Point2d> UndistortPoints(const CameraIntrinsics& camera,
                                         const std::vector<cv::Point2d>& pixels) {
  if (pixels.empty() || camera.distortion.empty()) return pixels;
  const cv::Mat k(CameraMatrix(camera));
  const cv::Mat d = Coefficients(camera);
  const cv::TermCriteria until(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12);
  std::vector<cv::Point2d> out;
  if (camera.model == LensModel::kFisheye) {
    cv::fisheye::undistortPoints(pixels, out, k, d, cv::noArray(), k, until);
    // Beyond the model's invertible range OpenCV returns (-1e6, -1e6).
    for (cv::Point2d& p : out) {
      if (p.x == -1e6 && p.y == -1e6) p = cv::Point2d(NAN, NAN);
    }
  } else {
    cv::undistortPoints(pixels, out, k, d, cv::noArray(), k, until);
  }
  return out;
}

}  // namespace chromatag
