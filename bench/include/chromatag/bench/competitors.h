// The three detectors compared, behind one small interface: each takes the
// same 8-bit BGR frame and returns detections of the families it was made for
// (16h5, 36h11 or both) with their corners in the tag's own orientation (spec section 7: top-left
// of the upright tag first, then clockwise; pixel centres at integer coordinates), so that every
// detector is scored against the same ground truth.
#ifndef CHROMATAG_BENCH_COMPETITORS_H_
#define CHROMATAG_BENCH_COMPETITORS_H_

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/bench/dataset.h"
#include "chromatag/bench/miss_analysis.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag::bench {

struct FoundTag {
  int id = -1;
  std::array<cv::Point2d, 4> corners;  // Spec section 7 order and pixel convention.
  std::string family = "16h5";         // "16h5" or "36h11".
  // ChromaTag's inner ring corners, green/black then red/green, each in the
  // order of `corners` (no allocation: the conversion is inside the timed
  // call). Detectors without them leave has_inner_corners false.
  bool has_inner_corners = false;
  std::array<cv::Point2d, 8> inner_corners{};
  // ChromaTag's Detection::corner_covariance; zero for the other detectors.
  cv::Matx<double, 8, 8> corner_covariance = cv::Matx<double, 8, 8>::zeros();
  // AprilTag 3's own homography (apriltag_detection_t::H, row-major), for its
  // pose; zero for the other detectors.
  std::array<double, 9> apriltag_h{};
};

// A tag's pose: camera_from_tag in the spec's tag frame (x right, y up, z
// towards the viewer).
struct PoseEstimate {
  cv::Matx33d rotation = cv::Matx33d::eye();
  cv::Vec3d translation;
  // ChromaTag's TagPose::covariance (ROS order: translation, then a small
  // rotation about the camera's axes composed onto `rotation`); the other
  // detectors give none.
  bool has_covariance = false;
  cv::Matx66d covariance = cv::Matx66d::zeros();
};

class TagDetector {
 public:
  virtual ~TagDetector() = default;
  virtual const std::string& name() const = 0;
  // Detects tags in `bgr` (CV_8UC3). Everything the detector needs to
  // do with a colour camera frame is inside this call (AprilTag's grey
  // conversion too), so that timing it times the whole job.
  virtual void Detect(const cv::Mat& bgr, std::vector<FoundTag>* found) = 0;
  // The pose of `tag`, one of this detector's detections, as a user of the
  // detector gets it: `tag_size` the black square's side, the camera `k`
  // without distortion. Not part of the timed call. The default is OpenCV's
  // solvePnP with SOLVEPNP_IPPE_SQUARE on the four corners (what ArUco's
  // estimatePoseSingleMarkers does). False when there is none.
  virtual bool Pose(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
                    PoseEstimate* pose) const;
};

// Families are named "16h5" and "36h11" (TagFamily::Names()); each maker
// returns nullptr and sets *error for an empty list or another name.

// libapriltag 3 with its defaults (quad_decimate 2, refine_edges on, two bits
// corrected), one thread, every family added to one detector.
std::unique_ptr<TagDetector> MakeAprilTagDetector(
    const std::vector<std::string>& families = {"16h5"}, std::string* error = nullptr);

// OpenCV's ArUco module (opencv_contrib 4.6) with DetectorParameters::create()
// defaults and DICT_APRILTAG_16h5 and/or DICT_APRILTAG_36h11: one
// detectMarkers call per dictionary, all inside the one timed Detect.
std::unique_ptr<TagDetector> MakeArucoDetector(const std::vector<std::string>& families = {"16h5"},
                                               std::string* error = nullptr);

// The covariance a user of a detector that gives none could put on its
// pose (what apriltag_ros would need instead of its zeros): ChromaTag's
// (EstimateTagPose) for `tag`'s four corners taken as a detection made by
// hand, each coordinate off by `sigma_px` independently, the inner corners
// placed from the four (they add nothing). False when it cannot be had.
bool AssumedPoseCovariance(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
                           double sigma_px, cv::Matx66d* covariance);

// This project's detector (default DetectorOptions, the given families, as
// `chromatag detect --family all` for both; or the options given). The last frame's summary
// (rejections; no stage times) is kept; TimeStages gives Tables 2 and 4 theirs.
class ChromaTagDetector : public TagDetector {
 public:
  static std::unique_ptr<ChromaTagDetector> Create(
      const std::vector<std::string>& families = {"16h5"}, std::string* error = nullptr);
  // With `options` (their families; report_rejected is the detector's own
  // business and ignored), e.g. a config from `chromatag calibrate`.
  static std::unique_ptr<ChromaTagDetector> CreateWithOptions(const DetectorOptions& options,
                                                              std::string* error = nullptr);
  ~ChromaTagDetector() override;
  const std::string& name() const override;
  void Detect(const cv::Mat& bgr, std::vector<FoundTag>* found) override;
  // EstimateTagPose: all twelve ring corners (FoundTag::inner_corners).
  bool Pose(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
            PoseEstimate* pose) const override;
  const DetectorSummary& last_summary() const;
  // Runs the detector again on `bgr` with DetectorOptions::time_stages on
  // and returns its summary: each stage's time. Timing the stages reads the
  // clock around each candidate's stages, so this is never part of a timed
  // call either.
  const DetectorSummary& TimeStages(const cv::Mat& bgr);

  // Runs the detector again on `bgr`, with rejected candidates reported,
  // and says why the tag of `truth` (a tagged frame) was missed: Table 4(b).
  // Reporting rejections costs time, so this is never part of a timed call.
  MissCause ExplainMiss(const cv::Mat& bgr, const FrameTruth& truth);

 private:
  struct Impl;
  explicit ChromaTagDetector(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// How each library orders its corners, as indices into its own output for
// the upright tag's top-left, top-right, bottom-right and bottom-left. The
// same for 16h5 and 36h11 (bench_support_test checks both).
// libapriltag: its homography maps the tag's (-1, 1), (1, 1), (1, -1),
// (-1, -1) to p[0..3], with the tag's y along the rows of its upright picture
// (downwards), so p[0] is the bottom-left and the order runs counter-clockwise
// on screen.
inline constexpr std::array<int, 4> kAprilTagCornerOrder = {3, 2, 1, 0};
// OpenCV 4.6 ArUco: clockwise from its own corner 0, but its DICT_APRILTAG_*
// codes are stored turned by 180 degrees against libapriltag's pictures, so
// on a printed AprilTag corner 0 is the bottom-right (a known OpenCV issue,
// opencv/opencv-python#1195, fixed for OpenCV 5). DICT_APRILTAG_36h11 is
// turned the same way.
inline constexpr std::array<int, 4> kArucoCornerOrder = {2, 3, 0, 1};
// libapriltag puts pixel centres at half-integer coordinates (its corners
// come out +0.5 px in x and y against OpenCV's convention); this is
// subtracted so all three share spec section 7's convention.
inline constexpr double kAprilTagPixelCentre = 0.5;
// bench_support_test checks the three on rendered frames: an order mistake
// shows as errors of a whole side, a convention mistake as a half-pixel bias.

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_COMPETITORS_H_
