// One trial of the camera calibration comparison (bench/calib_comparison.cc):
// a ChromaTag board and a ChArUco board of the same size, photographed by
// the same camera at the same poses through the same blur, noise and JPEG,
// each found and fitted by its own tools (ChromaTag's CalibrateCamera,
// OpenCV's calibrateCameraCharuco). Private to calib_comparison.
#ifndef CHROMATAG_BENCH_SRC_CALIB_TRIAL_H_
#define CHROMATAG_BENCH_SRC_CALIB_TRIAL_H_

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/aruco/charuco.hpp>
#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/options.h"
#include "page_view.h"

namespace chromatag::bench {

inline constexpr int kImageWidth = 752, kImageHeight = 480;

// The camera every trial recovers: the calibration tests' camera
// (testing::BarrelCamera: 752 x 480, fx 600, the principal point off the
// image centre, strong barrel distortion, k1 -0.25).
CameraIntrinsics TrueCamera();

enum CalibrationTool { kChromaTagBoard = 0, kCharucoBoard = 1 };
inline constexpr int kNumCalibrationTools = 2;
const char* CalibrationToolName(int tool);  // "ChromaTag", "ChArUco".

// A board as printed. Its page's frame (PrintedPage::origin_mm) has x right
// and y up the page, metres; `outline` is the pattern's outer corners in it
// and `centre` their middle, where every pose aims.
struct PrintedBoard {
  testing::PrintedPage page;
  std::array<cv::Point3d, 4> outline;
  cv::Vec3d centre;
  double width_mm = 0, height_mm = 0;
  std::string description;  // For the report.
};

// Both boards and the tools that find them, made once for every trial.
struct CalibrationSetup {
  PrintedBoard chromatag;
  Board chromatag_board;
  std::unique_ptr<Detector> chromatag_detector;
  PrintedBoard charuco;
  cv::Ptr<cv::aruco::CharucoBoard> charuco_board;  // Its frame: origin top-left, y down.
  cv::Ptr<cv::aruco::DetectorParameters> charuco_parameters;
};

// Nullopt (and *error) when the generator or the detector refuses its options.
std::optional<CalibrationSetup> MakeCalibrationSetup(std::string* error);

struct TrialOptions {
  int views = 20;     // Board poses per trial, each photographed for both boards.
  unsigned seed = 1;  // Trial t draws its poses and camera effects from (seed, t).
  int render_threads = 1;
};

// How one view was taken (the same for both boards).
struct ViewConditions {
  double tilt_deg = 0, axis_deg = 0, spin_deg = 0;
  double fill = 0;  // The board's width over the image's, as if face-on at the centre's depth.
  double blur_sigma_px = 0;
  int jpeg_quality = 0;     // 0: no JPEG.
  bool partly_out = false;  // A corner of the ChromaTag board's pattern falls outside the frame.
};

struct CalibrationOutcome {
  bool ok = false;
  std::string error;  // When not ok.
  CameraIntrinsics camera;
  double rms_px = 0;
  int views_used = 0;
  int corners_used = 0;
  double detect_ms_per_view = 0;  // One thread, mean over the trial's views.
  double calibrate_ms = 0;        // One thread.
  // The corners found (before the fit leaves any out) against where the true
  // camera puts them: the median distance, pixels.
  double corner_error_px = 0;
  // Where the tool's corners put a pixel's centre: 0 for OpenCV's projection
  // functions and ChromaTag, 0.5 for OpenCV 4.6's ChArUco corners
  // (interpolateCornersCharuco adds half a pixel to what its cornerSubPix
  // finds). Moving every corner moves the principal point by as much and
  // leaves the rest of the fit as it was.
  double pixel_centre = 0;
  double corner_error_own_px = 0;  // As corner_error_px, the truth moved by pixel_centre.
  // ChromaTag only: each view's board pose (EstimateBoardPose with the true
  // camera) against the truth, in its covariance's terms
  // (PoseNormalisedError): per axis error over sigma, and the squared
  // Mahalanobis distance. Views without a pose are left out.
  std::vector<std::array<double, 6>> board_pose_z;
  std::vector<double> board_pose_nees;
};

struct TrialResult {
  std::vector<ViewConditions> views;
  std::array<CalibrationOutcome, kNumCalibrationTools> outcome;
  double render_s = 0;  // Wall time, on TrialOptions::render_threads threads.
};

// Renders the trial's views on render_threads threads, then detects and
// calibrates on the calling thread (OpenCV's own threads should be off).
TrialResult RunCalibrationTrial(const CalibrationSetup& setup, const TrialOptions& options,
                                int trial);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_SRC_CALIB_TRIAL_H_
