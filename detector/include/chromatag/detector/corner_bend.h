// Where the detector puts a tag's corners when a lens bends the tag's
// sides. The detector fits a straight line to each side of the black square
// and places the inner ring corners by the homography of the four outer
// ones. Through a distorting lens the sides are curves, so both miss the
// corners' true projections, by more the further from the image's centre
// and the larger the tag: in camera_calibration_test's rendered views
// (k1 = -0.25, tags 45-70 px), the corners 300-400 px from the centre lay
// 0.16 px outwards (the black square's) and 0.08 and 0.22 px inwards (the
// inner rings') on average. A fit that takes the detected corners as they are
// takes that bend for the pose, or for the lens's distortion and focal
// length. EstimateTagPose, EstimateBoardPose and CalibrateCamera take it off
// before their final fit; code that fits detections to a lens model of its
// own can do the same with these functions.
#ifndef CHROMATAG_DETECTOR_CORNER_BEND_H_
#define CHROMATAG_DETECTOR_CORNER_BEND_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

// Whether `camera` has a distortion coefficient other than zero (without,
// straight sides stay straight and the bend is zero).
bool HasDistortion(const CameraIntrinsics& camera);

// For one tag's twelve ring corners in some object frame (TagRingCorners'
// or BoardTagCorners' order: the black square's four, clockwise, first),
// seen by `camera` with camera_from_object (rvec, tvec): where the detector
// puts each corner less where it projects, pixels. The outer corners are
// where total least squares lines through each side's projection meet (over
// the part of the side the detector samples); the inner ones are placed from
// them as the detector places them. Zeros when the corners do not project.
std::vector<cv::Point2d> CornerBend(const CameraIntrinsics& camera,
                                    const std::vector<cv::Point3d>& ring_corners,
                                    const cv::Vec3d& rvec, const cv::Vec3d& tvec);

// `detection` with `bend` (CornerBend's, twelve) taken off its corners: the
// corners a detector without the straight-side error would have reported.
// The rest of the detection is kept.
Detection Straightened(const Detection& detection, const std::vector<cv::Point2d>& bend);

// The inner ring corners' place in the black square, from the twelve
// corners in an object frame: coordinates along the square's first and last
// sides, (0, 0) at its first corner and (1, 1) at its third.
std::vector<cv::Point2d> InnerCornersInSquare(const std::vector<cv::Point3d>& ring_corners);

// Where the detector places inner corners at `in_square` (as
// InnerCornersInSquare gives them) from the black square's four image
// corners `outer`: the homography taking the unit square to them.
std::vector<cv::Point2d> PlaceInnerCorners(const std::array<cv::Point2d, 4>& outer,
                                           const std::vector<cv::Point2d>& in_square);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_CORNER_BEND_H_
