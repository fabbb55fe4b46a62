// Points through a camera's lens, in either of CameraIntrinsics' models
// (OpenCV's radial-tangential or cv::fisheye's equidistant model).
#ifndef CHROMATAG_DETECTOR_CAMERA_H_
#define CHROMATAG_DETECTOR_CAMERA_H_

#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/options.h"

namespace chromatag {

// [fx 0 cx; 0 fy cy; 0 0 1].
cv::Matx33d CameraMatrix(const CameraIntrinsics& camera);

// `points` in a frame whose pose in the camera is (rvec, tvec), through the
// lens to pixels. Points behind the camera come out mirrored: check first.
std::vector<cv::Point2d> ProjectPoints(const CameraIntrinsics& camera,
                                       const std::vector<cv::Point3d>& points,
                                       const cv::Vec3d& rvec, const cv::Vec3d& tvec);

// Pixels of the real lens to where an ideal pinhole camera with the same
// camera matrix would see them; iterated to convergence (OpenCV's default
// five iterations leave up to a quarter pixel near the edge of a strongly
// distorted image). NaN for a pixel the fisheye model cannot invert.
std::vector<cv::Point2d> UndistortPoints(const CameraIntrinsics& camera,
                                         const std::vector<cv::Point2d>& pixels);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_CAMERA_H_
