// Points through a camera's lens, in either of CameraIntrinsics' models
// (OpenCV's radial-tangential or cv::fisheye's equidistant model).
#ifndef CHROMATAG_DETECTOR_CAMERA_H_
#define CHROMATAG_DETECTOR_CAMERA_H_

#include <optional>
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

// The intrinsics of a camera calibrated on frames of `calibrated` pixels,
// for frames of `frame` pixels. The same size: `camera` as it is. The same
// aspect (the two scales within 0.5 %): fx, fy, cx and cy scaled, with pixel
// centres at integers (a pixel's edge at -0.5 stays at -0.5), the lens
// distortion unchanged (it is in normalised coordinates). Another shape
// (a cropped or stretched frame): nullopt, as no scaling holds; calibrate
// at that size.
std::optional<CameraIntrinsics> IntrinsicsForFrame(const CameraIntrinsics& camera,
                                                   cv::Size calibrated, cv::Size frame);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_CAMERA_H_
