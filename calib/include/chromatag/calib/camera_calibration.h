// Camera intrinsics from views of a ChromaTag board (a sheet written by
// `chromatag generate --board`, a colour calibration sheet, or any planar
// board file): the twelve ring corners of every board tag in every view,
// fitted by OpenCV's calibrateCamera (pinhole with k1, k2, p1, p2 and
// optionally k3) or cv::fisheye::calibrate (the equidistant model). Tags and
// views whose corners disagree with the fit are left out and named, a view
// given twice (every corner within a pixel of an earlier view's) is used
// once, and the result says which parameters the views leave weakly
// constrained.
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
  LensModel model = LensModel::kPinhole;
  bool fit_k3 = false;  // Pinhole: k3 as well as k1, k2, p1, p2.
  // A view is used with at least this many board tags in it.
  int min_tags_per_view = 2;
  // A tag that disagrees with the others in its view under the first fit's
  // camera (EstimateBoardPose leaves it out: a misread ID, a tag not where
  // the board says) is left out of that view. After each fit, a view whose
  // corners reproject worse than max_view_rms_px (rms) is left out, and so
  // is a tag with a corner further than max_corner_error_px, or
  // corner_error_factor times the fit's rms if that is more, from where the
  // fit puts it.
  double max_view_rms_px = 2.0;
  double max_corner_error_px = 1.0;
  double corner_error_factor = 5.0;
  // Where ProjectionCheck judges the model: this far from the camera,
  // metres; 0 for the median distance of the used views' boards.
  double working_distance = 0.0;

  bool IsValid(std::string* error) const;
};

struct CalibrationViewResult {
  std::string name;
  bool used = false;
  std::string why_not;                    // When not used.
  int tags = 0;                           // Board tags used in the view.
  std::vector<int> tags_left_out;         // IDs of detections left out of the view.
  std::vector<std::string> why_left_out;  // Per entry of tags_left_out.
  double rms_px = 0.0;
  cv::Vec3d rvec, tvec;   // camera_from_board for the view.
  double tilt_deg = 0.0;  // Between the board's normal and the optical axis.
  // Used views: every used corner as detected and its residual (fitted
  // projection minus the corner straightened for the lens's bend,
  // chromatag/detector/corner_bend.h), pixels.
  std::vector<cv::Point2d> corners;
  std::vector<cv::Point2d> residuals;
};

// How well the fitted model projects, over the image, at a working distance
// (as mrcal measures it). Maps are grid.width x grid.height cells,
// row-major, each value at its cell's centre.
struct ProjectionCheck {
  double distance = 0.0;  // Metres.
  cv::Size grid;
  // One standard deviation of where the model projects the point it sees at
  // the cell's centre, `distance` away, from the intrinsics' covariance (the
  // larger axis of its ellipse), px: the views' poses marginalised out, and
  // what a turn of the camera frame would absorb taken out.
  std::vector<double> uncertainty_px;
  // How far apart the models fitted to two halves of the views (every
  // other used view) project the same point, the camera frames aligned by
  // the rotation that best matches their rays, px. Empty with fewer than six
  // used views.
  std::vector<double> cross_validation_px;
  // The standard deviation of cross_validation_px that noise alone would
  // give: the two halves' own projection uncertainties (as uncertainty_px,
  // each half's), the root of the sum of their squares, px.
  std::vector<double> cross_validation_expected_px;
  // Whether a central cell's difference is over kMaxCrossValidationPx and
  // over kCrossValidationSigmas times what noise explains there: the views
  // disagree on the lens (a bent or moving board, a lens the model does not
  // fit). Otherwise a difference over the limit means too few views.
  bool cross_validation_beyond_noise = false;
  // Over the central 80 % of the image (10 % off each side): the median and
  // the largest cell; NaN when not computed.
  double uncertainty_median_px = 0.0, uncertainty_worst_px = 0.0;
  double cross_validation_median_px = 0.0, cross_validation_worst_px = 0.0;
};

// The limits CameraCalibration::doubts holds ProjectionCheck's worst central
// figures to, px.
inline constexpr double kMaxProjectionUncertaintyPx = 0.3;
inline constexpr double kMaxCrossValidationPx = 0.3;
// A cross-validation difference over this many of its expected standard
// deviations is more than noise (ProjectionCheck::cross_validation_beyond_noise).
inline constexpr double kCrossValidationSigmas = 3.0;
// Used views whose boards' distances span less than this ratio (furthest
// over nearest) are "at one distance": the fit then cannot tell the focal
// length from the distance, nor the distortion at other depths.
inline constexpr double kMinDistanceSpread = 1.3;

struct CameraCalibration {
  CameraIntrinsics camera;  // fx, fy, cx, cy, the model and its distortion.
  cv::Size image_size;
  double rms_px = 0.0;  // Over every corner used.
  int corners_used = 0;
  // One standard deviation of fx, fy, cx, cy and then each distortion
  // coefficient, from the fit's Jacobian and residuals.
  std::vector<double> std_dev;
  std::vector<CalibrationViewResult> views;
  // What the used views constrain weakly (no tilted views, corners only in
  // the middle of the image, few views), each a sentence saying what to add.
  std::vector<std::string> warnings;
  // What the fit does not pin down: fx, fy, cx and cy when fewer than two
  // views are tilted 20 degrees or more (views of a board facing the camera
  // leave the focal length to the distortion, whatever the deviations say),
  // fx or fy with a standard deviation over 0.5 % of its value, cx or cy
  // over 1 % of the image's side, every view at one distance
  // (kMinDistanceSpread), projection uncertainty or cross-validation over
  // their limits in the central 80 % of the image (or not measurable: fewer
  // than six views); each a sentence. A camera file written from such a fit
  // would claim what the views do not show; `calibrate-camera` writes none
  // unless asked.
  std::vector<std::string> doubts;
  ProjectionCheck projection;
};

// The names of CameraCalibration::std_dev's entries: "fx", "fy", "cx", "cy",
// "k1", ... for the camera's model.
std::vector<std::string> CalibrationParameterNames(const CameraIntrinsics& camera);

// Whether `board` can calibrate a camera: valid, planar (every tag at z = 0
// and facing +z) and with at least options.min_tags_per_view tags; false
// with *error saying what is wrong. CalibrateCamera checks this first.
bool CheckCalibrationBoard(const Board& board, const CameraCalibrationOptions& options,
                           std::string* error = nullptr);

// nullopt (and *error) for a board that is not planar (every tag's z 0 and
// its axes the board's), an empty image size, invalid options, or fewer
// than three usable views (a repeated view counts once), and when the fit
// itself fails.
std::optional<CameraCalibration> CalibrateCamera(const Board& board,
                                                 const std::vector<CalibrationView>& views,
                                                 cv::Size image_size,
                                                 const CameraCalibrationOptions& options = {},
                                                 std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CAMERA_CALIBRATION_H_
