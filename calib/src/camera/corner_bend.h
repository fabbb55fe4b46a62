// Where the detector puts a tag's corners when the lens bends its sides
// (internal to calib). The detector fits a straight line to each side of
// the black square and places the inner corners by the homography of the
// four outer ones; through a distorting lens the sides are curves, so both
// miss the corners' true projections, by more the further from the image's
// centre and the larger the tag (a 50 px tag 300 px from the centre of a
// k1 = -0.25 lens: about 0.15 px outwards at the outer corners, 0.2 px
// inwards at the inner ones). A calibration that fitted the detected
// corners as they are would take that bend for the lens's distortion and
// its focal length, differently in every view.
#ifndef CHROMATAG_CALIB_SRC_CAMERA_CORNER_BEND_H_
#define CHROMATAG_CALIB_SRC_CAMERA_CORNER_BEND_H_

#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/options.h"

namespace chromatag::internal {

// A tag's ring corners (BoardTagCorners): the black square's four, then the
// green/black square's and the red/green one's.
inline constexpr int kRingCorners = 12;

// For one tag's twelve ring corners on the board (BoardTagCorners' order:
// the black square's four first, clockwise), seen by `camera` with
// camera_from_board (rvec, tvec): where the detector would put each corner
// less where it projects (pixels). The outer corners are where total least
// squares lines through each side's projection (over the middle 76 % of the
// side, as the detector samples it) meet; the inner corners are the
// outer ones' homography at the inner corners' place in the square.
// The inner ring corners' place in the black square (BoardTagCorners'
// order, the square's four first): coordinates along its first and last
// sides, (0, 0) at its first corner and (1, 1) at its third.
std::vector<cv::Point2d> InnerCornersInSquare(const std::vector<cv::Point3d>& ring_corners);

// Where the detector places inner corners at `in_square` (as
// InnerCornersInSquare gives them) from the square's four image corners:
// the homography taking the unit square to them.
std::vector<cv::Point2d> PlaceInnerCorners(const cv::Point2d (&outer)[4],
                                           const std::vector<cv::Point2d>& in_square);

std::vector<cv::Point2d> CornerBend(const CameraIntrinsics& camera,
                                    const std::vector<cv::Point3d>& ring_corners,
                                    const cv::Vec3d& rvec, const cv::Vec3d& tvec);

}  // namespace chromatag::internal

#endif  // CHROMATAG_CALIB_SRC_CAMERA_CORNER_BEND_H_
