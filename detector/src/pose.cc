#include "chromatag/detector/pose.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/detector/corner_bend.h"

#include "pose_fit.h"

namespace chromatag {

namespace {

// EstimateTagPose on the detection's corners as they are; the covariance
// only `with_covariance`.
bool FitTagPose(const Detection& detection, const CameraIntrinsics& camera, double tag_size,
                bool with_covariance, TagPose* pose, std::string* error) {
  using namespace internal;
  // The refinement works in undistorted pixels of the same camera matrix.
  std::vector<cv::Point2d> image;
  if (!UndistortedRingCorners(detection, camera, &image, error)) return false;
  const std::vector<cv::Point3d> object = TagRingCorners(*detection.family, tag_size);
  const cv::Matx33d k = CameraMatrix(camera);
  const std::vector<PoseFit> fits = TagPoseFits(object, image, k);
  if (fits.empty()) {
    if (error) *error = "no pose puts the tag in front of the camera";
    return false;
  }
  cv::Vec3d rvec;
  cv::Rodrigues(Orthonormal(fits[0].rotation), rvec);
  if (!Finite(rvec) || !Finite(fits[0].translation)) {
    if (error) *error = "the pose is not finite";
    return false;
  }
  pose->rvec = rvec;
  pose->tvec = fits[0].translation;
  pose->rms_error_px = fits[0].rms_px;
  pose->ambiguity = Ambiguity(fits);
  if (!with_covariance) return true;
  CornerNoise noise;
  if (!TagCornerNoise(detection, camera, object, &noise)) {
    if (error) *error = "a corner lies beyond the range of the camera's lens model";
    return false;
  }
  pose->covariance = PoseCovariance({&noise}, fits[0], Rival(fits), k);
  return true;
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
  const bool distorted = HasDistortion(camera);
  if (!FitTagPose(detection, camera, tag_size, !distorted, pose, error)) return false;
  if (!distorted) return true;
  // The lens bends the tag's sides (corner_bend.h): the pose once more, with
  // its covariance, from the corners straightened under the first.
  const std::vector<cv::Point3d> object = internal::TagRingCorners(*detection.family, tag_size);
  const Detection straight =
      Straightened(detection, CornerBend(camera, object, pose->rvec, pose->tvec));
  if (FitTagPose(straight, camera, tag_size, true, pose, nullptr)) return true;
  // Straightened corners beyond the lens model's range: the pose from the
  // corners as they are, with its covariance.
  return FitTagPose(detection, camera, tag_size, true, pose, error);
}

PoseSigma SigmaOf(const cv::Matx66d& covariance) {
  PoseSigma sigma;
  sigma.translation =
      std::sqrt(std::max(0.0, covariance(0, 0) + covariance(1, 1) + covariance(2, 2)));
  sigma.rotation = std::sqrt(std::max(0.0, covariance(3, 3) + covariance(4, 4) + covariance(5, 5)));
  return sigma;
}

}  // namespace chromatag
