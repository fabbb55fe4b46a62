// How well a fitted camera model projects, over the image (internal to
// calib): the intrinsics' covariance from the fit's Jacobian, the
// projection uncertainty it implies at a working distance, and the
// difference between the models two halves of the views give. The measures
// follow mrcal's (projection uncertainty, cross-validation); the code is
// this project's.
#ifndef CHROMATAG_CALIB_SRC_CAMERA_PROJECTION_CHECK_H_
#define CHROMATAG_CALIB_SRC_CAMERA_PROJECTION_CHECK_H_

#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/calib/camera_calibration.h"
#include "chromatag/detector/options.h"

namespace chromatag::internal {

// `points` (in the frame of rvec, tvec) projected by `camera`, and the
// projections' Jacobian over the fitted intrinsics (fx, fy, cx, cy, then the
// distortion coefficients: k3 only with `fit_k3` for the pinhole model;
// CameraCalibration::std_dev's order) and over the pose (rvec, tvec): two
// rows per point.
void ProjectWithJacobians(const CameraIntrinsics& camera, const std::vector<cv::Point3d>& points,
                          const cv::Vec3d& rvec, const cv::Vec3d& tvec, bool fit_k3,
                          std::vector<cv::Point2d>* projected, cv::Mat* intrinsic_jacobian,
                          cv::Mat* pose_jacobian);

// The covariance of the fitted intrinsics (ProjectWithJacobians' order),
// every view's pose marginalised out. Each view's points come in groups of
// `corners_per_tag` (a tag's ring corners, BoardTagCorners' order) of which
// only the first four are measured, the others placed from them by the
// homography of the square (as the detector places them); with
// `corners_per_tag` 1 (or not dividing a view's points) each point is
// measured on its own. The fit weighs every point alike, so the covariance
// is the sandwich S^-1 (sum_v M_v^T G G^T M_v) S^-1 sigma^2: S the reduced
// normal matrix A - sum_v B_v D_v^-1 B_v^T of J^T J = [A B; B^T D] (D
// block-diagonal: each view's pose touches only its own corners, so the
// time is linear in the views), M_v = J_i - J_p D_v^-1 B_v^T how a point's
// error moves the intrinsics once the view's pose has taken its share, G
// how the placed points move with the measured ones, and sigma^2 the
// measured points' residual variance over their count less the
// parameters. With every point measured it is sigma^2 S^-1.
cv::Mat IntrinsicCovariance(const CameraIntrinsics& camera,
                            const std::vector<std::vector<cv::Point3d>>& object,
                            const std::vector<std::vector<cv::Point2d>>& image,
                            const std::vector<cv::Vec3d>& rvecs,
                            const std::vector<cv::Vec3d>& tvecs, bool fit_k3, int corners_per_tag);

// The cells the maps are taken on: kProjectionGrid across, and down in
// proportion to the image.
inline constexpr int kProjectionGrid = 24;

// ProjectionCheck::uncertainty_px for `camera` with intrinsics covariance
// `covariance` at `distance` metres, on the grid of `grid` cells over
// `image_size`: at each cell's centre, the point the model sees there at
// that distance projected again, its 2 x 2 covariance from the intrinsics'
// less what a turn of the camera frame absorbs (the turn that best undoes
// a change of the intrinsics over the central 80 % of the image: the frame
// is the fit's to choose, as in CrossValidationMap), and the square root of
// its larger eigenvalue (px).
std::vector<double> UncertaintyMap(const CameraIntrinsics& camera, const cv::Mat& covariance,
                                   bool fit_k3, double distance, cv::Size image_size,
                                   cv::Size grid);

// ProjectionCheck::cross_validation_px: at each cell's centre, the point
// model `a` sees there at `distance` metres, turned by the rotation that
// best aligns a's rays with b's over the central 80 % of the image (the
// camera frame is the fit's to choose), projected by `b`; its distance from
// the cell's centre, px.
std::vector<double> CrossValidationMap(const CameraIntrinsics& a, const CameraIntrinsics& b,
                                       double distance, cv::Size image_size, cv::Size grid);

// The median and the largest of `map` over the cells whose centres lie in
// the central 80 % of the image (10 % off each side).
void CentralFigures(const std::vector<double>& map, cv::Size image_size, cv::Size grid,
                    double* median, double* worst);

// Whether some cell whose centre lies in the central 80 % of the image has
// `difference` over `limit` and over `sigmas` times `expected`.
bool BeyondNoise(const std::vector<double>& difference, const std::vector<double>& expected,
                 cv::Size image_size, cv::Size grid, double limit, double sigmas);

}  // namespace chromatag::internal

#endif  // CHROMATAG_CALIB_SRC_CAMERA_PROJECTION_CHECK_H_
