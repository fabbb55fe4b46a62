#include "chromatag/detector/pose.h"

#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "chromatag/families/family.h"

namespace chromatag {
namespace {

// The corners of a square of side `side` centred on the tag origin, in the
// spec's tag frame (x right, y up): top-left, then clockwise as seen from the
// front, matching Detection::corners.
void AddSquare(double side, std::vector<cv::Point3d>* points) {
  const double h = 0.5 * side;
  points->push_back({-h, h, 0});
  points->push_back({h, h, 0});
  points->push_back({h, -h, 0});
  points->push_back({-h, -h, 0});
}

}  // namespace

bool EstimateTagPose(const Detection& detection, const CameraIntrinsics& camera, double tag_size,
                     TagPose* pose, std::string* error) {
  if (!camera.IsValid(error)) return false;
  if (!(tag_size > 0.0) || !std::isfinite(tag_size)) {
    if (error) *error = "tag size must be a positive length";
    return false;
  }
  if (detection.family == nullptr) {
    if (error) *error = "the detection has no family";
    return false;
  }
  const double cells = detection.family->black_square_cells();
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat distortion(camera.distortion, /*copyData=*/true);

  std::vector<cv::Point3d> object;
  AddSquare(tag_size, &object);
  std::vector<cv::Point2d> image(detection.corners.begin(), detection.corners.end());
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(object, image, k, distortion, rvec, tvec, false, cv::SOLVEPNP_IPPE_SQUARE)) {
    if (error) *error = "solvePnP found no pose";
    return false;
  }
  // The green/black square is d of the d + 2 cells, the red/green one d - 2.
  AddSquare(tag_size * (cells - 2) / cells, &object);
  AddSquare(tag_size * (cells - 4) / cells, &object);
  image.insert(image.end(), detection.green_corners.begin(), detection.green_corners.end());
  image.insert(image.end(), detection.red_corners.begin(), detection.red_corners.end());
  cv::solvePnPRefineLM(object, image, k, distortion, rvec, tvec);

  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, rvec, tvec, k, distortion, projected);
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const cv::Point2d d = projected[i] - image[i];
    sum += d.dot(d);
  }
  pose->rvec = cv::Vec3d(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
  pose->tvec = cv::Vec3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  pose->rms_error_px = std::sqrt(sum / static_cast<double>(image.size()));
  return true;
}

}  // namespace chromatag
