// Boards and bundles: tags fixed rigidly to one body (a printed sheet, a
// grid, tags mounted on a robot), and the body's pose from every corner of
// every tag of it the detector found (docs/pose.md, "Boards and bundles").
// Reading board files (a sheet's sidecar, an apriltag_ros-style bundle
// YAML) is rig's: chromatag/rig/board_file.h.
#ifndef CHROMATAG_DETECTOR_BOARD_H_
#define CHROMATAG_DETECTOR_BOARD_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

// One tag of a board: where it sits on the body. The tag frame is the
// spec's (origin at the black square's centre, x right, y up, z out of the
// tag towards the viewer); body_from_tag maps it into the board frame.
// The tag sizes and positions a board may hold, metres: from a millimetre
// to 10 m, within a kilometre of the board's origin on each axis (a file
// that says 1e300 says nothing a fit can use).
inline constexpr double kMinBoardTagSize = 0.001;
inline constexpr double kMaxBoardTagSize = 10.0;
inline constexpr double kMaxBoardReach = 1000.0;

struct BoardTag {
  std::string family;  // "16h5" or "36h11".
  int id = 0;
  double size = 0.0;                          // Side of the black square, metres.
  cv::Matx33d rotation = cv::Matx33d::eye();  // body_from_tag.
  cv::Vec3d translation{0, 0, 0};             // The tag's centre in the board frame, metres.
};

struct Board {
  std::string name;
  std::vector<BoardTag> tags;
  // The palette it is printed in, as its file names it (for people; the
  // detector reads every palette).
  std::string palette;

  // False with *error for no tags, a family name that is not 16h5 or 36h11,
  // a tag twice (the same family and ID), a size outside kMinBoardTagSize
  // to kMaxBoardTagSize, a rotation that is not one, a position further
  // than kMaxBoardReach from the board's origin on any axis.
  bool IsValid(std::string* error = nullptr) const;
  // The index of the tag with this family and ID, or -1.
  int Find(const std::string& family, int id) const;
};

// The twelve ring corners of `tag` (of `family`) in the board frame, in
// Detection's order: the black square's four (top-left of the upright tag
// first, clockwise), then the green/black square's and the red/green one's.
std::vector<cv::Point3d> BoardTagCorners(const BoardTag& tag, const TagFamily& family);

struct BoardPose {
  cv::Vec3d rvec;  // Rodrigues rotation of camera_from_board; norm at most pi.
  cv::Vec3d tvec;  // The board frame's origin in the camera frame, metres.
  // Board tags (indices into Board::tags, ascending) whose corners the pose
  // was fitted to.
  std::vector<int> tags_used;
  // Detections of board tags left out (indices into the detections given,
  // ascending): their corners disagree with the pose the others agree on (a
  // misread ID, a tag not where the board file says, a second copy of a tag).
  std::vector<int> detections_rejected;
  // Root mean square reprojection error over the used tags' ring corners
  // (twelve per tag), pixels.
  double rms_error_px = 0.0;
  // As TagPose::ambiguity, for the whole board: the kept pose's rms over that
  // of the best other local solution; 0 when there is none. A planar board
  // seen small or face-on may have a mirrored tilt that fits almost as well.
  double ambiguity = 0.0;
  // As TagPose::covariance, for the board frame's origin and axes: ROS's
  // order (x, y, z in metres, then a small rotation about the camera's axes
  // in radians), from the corners of the tags used.
  cv::Matx66d covariance = cv::Matx66d::zeros();
};

// The board's pose in the camera frame from the detections of its tags
// (those whose family and ID the board holds; others are ignored). Every tag
// proposes a pose (its planar solutions), the proposal most tags agree with
// is refined by Levenberg-Marquardt on all twelve ring corners of the tags
// that agree with it, and tags that still disagree are left out, so that
// one misread or misplaced tag does not pull the pose. One tag is enough.
// False (and *error) for invalid intrinsics or board, no tag of the board
// among the detections, or no pose that puts them in front of the camera.
bool EstimateBoardPose(const std::vector<Detection>& detections, const Board& board,
                       const CameraIntrinsics& camera, BoardPose* pose,
                       std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_BOARD_H_
