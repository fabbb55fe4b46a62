// Camera intrinsics from views of a ChromaTag board (a sheet written by
// `chromatag generate --board`, or any planar board file): the twelve ring
// corners of every board tag in every view, fitted by OpenCV's
// calibrateCamera (pinhole with k1, k2, p1, p2 and optionally k3). Views
// and tags whose corners disagree with the fit are left out and named.
//
// Not finished: the `calibrate-camera` command, automatic view selection
// from videos, the fisheye model, the ROS / Kalibr outputs and the report
// are still to come; this is the fit they will use.
#ifndef CHROMATAG_CALIB_CAMERA_CALIBRATION_H_
#define CHROMATAG_CALIB_CAMERA_CALIBRATION_H_

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

struct CalibrationView {
  std::string name;  // For messages: a file name, "frame 12", ...
  std::vector<Detection> detections;
};

struct CameraCalibrationOptions {
  bool fit_k3 = false;  // k3 as well as k1, k2, p1, p2.
  // A view is used with at least this many board tags in it.
  int min_tags_per_view = 2;
  // A tag that disagrees with the others in its view under the first fit's
  // camera (EstimateBoardPose leaves it out: a misread ID, a tag not where
  // the board says) is left out of that view; a view whose corners then
  // reproject worse than this (px, rms) is left out.
  double max_rms_px = 2.0;
};

struct CalibrationViewResult {
  std::string name;
  bool used = false;
  std::string why_not;             // When not used.
  int tags = 0;                    // Board tags used in the view.
  std::vector<int> tags_left_out;  // IDs of detections left out of the view.
  double rms_px = 0.0;
  cv::Vec3d rvec, tvec;  // camera_from_board for the view.
};

struct CameraCalibration {
  CameraIntrinsics camera;  // fx, fy, cx, cy; distortion k1, k2, p1, p2, k3.
  cv::Size image_size;
  double rms_px = 0.0;  // Over every corner used.
  // One standard deviation of fx, fy, cx, cy, k1, k2, p1, p2, k3 (OpenCV's
  // estimate from the fit's Jacobian).
  std::vector<double> std_dev;
  std::vector<CalibrationViewResult> views;
};

// False (and *error) for a board that is not planar (every tag's z 0 and
// its axes the board's), an empty image size, or fewer than three usable
// views.
std::optional<CameraCalibration> CalibrateCamera(const Board& board,
                                                 const std::vector<CalibrationView>& views,
                                                 cv::Size image_size,
                                                 const CameraCalibrationOptions& options = {},
                                                 std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CAMERA_CALIBRATION_H_
