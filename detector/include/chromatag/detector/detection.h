// What the detector returns: detections (spec section 7) and a per-frame
// summary with the time and the rejections of every stage (the paper's
// Tables 2 and 4).
#ifndef CHROMATAG_DETECTOR_DETECTION_H_
#define CHROMATAG_DETECTOR_DETECTION_H_

#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/families/family.h"

namespace chromatag {

// The tag's pose: camera_from_tag maps tag coordinates (origin at the tag
// centre, x right, y up, z out of the tag towards the viewer, metres; as
// OpenCV's SOLVEPNP_IPPE_SQUARE) to camera coordinates.
struct TagPose {
  cv::Vec3d rvec;  // Rodrigues rotation of camera_from_tag.
  cv::Vec3d tvec;  // Tag centre in the camera frame, metres.
  // Root mean square reprojection error over the twelve ring corners, pixels.
  double rms_error_px = 0.0;
};

struct Detection {
  // The decoded tag's family (16h5 or 36h11): its name, cell layout and
  // codes. Families are loaded once per process and never freed
  // (TagFamily::Load), so the pointer stays valid.
  const TagFamily* family = nullptr;
  int id = -1;
  int hamming = 0;  // Bits corrected.
  // How clearly the shades split: over both colours, the smaller gap between
  // the two b* clusters divided by their pooled spread (at least 1 b* unit).
  // Dimensionless; weak decodes below DetectorOptions::min_decision_margin
  // are rejected.
  double decision_margin = 0.0;
  // The black/white border, in the decoded tag's orientation: corner 0 is the
  // top-left of the upright tag, then clockwise. Pixel centres are at integer
  // coordinates (OpenCV's convention).
  std::array<cv::Point2d, 4> corners;
  // The green/black and red/green borders, in the same order.
  std::array<cv::Point2d, 4> green_corners;
  std::array<cv::Point2d, 4> red_corners;
  // Maps the upright black square, the unit square (0,0)-(1,1) with x right
  // and y down, to image pixels: (0,0) -> corners[0], (1,0) -> corners[1].
  cv::Matx33d image_from_tag;
  bool has_pose = false;
  TagPose pose;
};

// Algorithm 1's stages, in order.
enum class Stage { kFindADiff = 0, kInitialScan, kBuildPolygon, kPolyToQuad, kDecode };
inline constexpr int kNumStages = 5;
const char* StageName(Stage stage);  // "FindADiff", ...

struct DetectorSummary {
  // Wall time spent in each stage, microseconds. FindADiff is the frame's
  // time minus the other stages (its loop encloses them).
  std::array<double, kNumStages> stage_time_us{};
  // Candidates abandoned by each stage. FindADiff counts seeds whose rise
  // the coarse prefilter let through but the accurate a* did not confirm.
  std::array<int, kNumStages> rejected{};
  int seeds = 0;  // Candidates handed to InitialScan.
  double total_time_us = 0.0;
  double pose_time_us = 0.0;  // Included in Decode's time.
};

struct DetectionResult {
  std::vector<Detection> detections;
  DetectorSummary summary;
};

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_DETECTION_H_
