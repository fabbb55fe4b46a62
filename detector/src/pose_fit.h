// Pose fitting shared by the tag pose (pose.cc) and the board pose
// (board.cc): known points seen by a pinhole camera, started from planar
// solutions and refined by Levenberg-Marquardt in small rotations composed
// onto the estimate, so that no view is singular.
#ifndef CHROMATAG_DETECTOR_SRC_POSE_FIT_H_
#define CHROMATAG_DETECTOR_SRC_POSE_FIT_H_

#include <limits>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag::internal {

struct PoseFit {
  cv::Matx33d rotation = cv::Matx33d::eye();  // camera_from_object.
  cv::Vec3d translation;
  double rms_px = std::numeric_limits<double>::infinity();
};

// The twelve ring corners of a tag of `family` whose black square has side
// `tag_size`, in its tag frame (x right, y up, origin at the centre): the
// black square, the green/black and the red/green squares, each top-left
// first and clockwise as seen from the front, as Detection's corners.
std::vector<cv::Point3d> TagRingCorners(const TagFamily& family, double tag_size);

// The detection's twelve ring corners in the same order, lens distortion
// taken out (pixels of the same camera matrix). False with *error when a
// corner is not finite.
bool UndistortedRingCorners(const Detection& detection, const CameraIntrinsics& camera,
                            std::vector<cv::Point2d>* undistorted, std::string* error);

// `object` seen at `image` (undistorted pixels) by the pinhole camera `k`.
// Holds references: both must outlive it.
class Reprojection {
 public:
  Reprojection(const std::vector<cv::Point3d>& object, const std::vector<cv::Point2d>& image,
               const cv::Matx33d& k)
      : object_(object), image_(image), k_(k) {}

  // Sum of squared residuals; infinite when a point lies behind the camera.
  double Cost(const cv::Matx33d& r, const cv::Vec3d& t) const;
  // Root mean square residual, pixels.
  double Rms(const cv::Matx33d& r, const cv::Vec3d& t) const;
  // Refines `fit` in place by Levenberg-Marquardt and sets its rms.
  void Refine(PoseFit* fit) const;

 private:
  bool Normal(const cv::Matx33d& r, const cv::Vec3d& t, cv::Matx66d* jtj, cv::Vec6d* jte) const;

  const std::vector<cv::Point3d>& object_;
  const std::vector<cv::Point2d>& image_;
  cv::Matx33d k_;
};

// A tag's candidate poses from its twelve corners: both planar solutions of
// the outer square (OpenCV's SOLVEPNP_IPPE_SQUARE) and the one its
// homography gives, each refined on all twelve; best (smallest rms) first.
// Empty when none puts the tag in front of the camera.
std::vector<PoseFit> TagPoseFits(const std::vector<cv::Point3d>& object,
                                 const std::vector<cv::Point2d>& image, const cv::Matx33d& k);

// The nearest rotation matrix (SVD).
cv::Matx33d Orthonormal(const cv::Matx33d& m);

// The angle of the rotation that takes `a` to `b`, radians.
double AngleBetween(const cv::Matx33d& a, const cv::Matx33d& b);

bool Finite(const cv::Vec3d& v);

// What one tag's corners tell a pose fit, and how well: its twelve ring
// corners in the fitted body's frame and where they were seen
// (undistorted), how those image points move with the four corners the
// detector measured (the inner corners are placed from the outer ones, and
// lens distortion is taken out after), and the four corners' covariance.
struct CornerNoise {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  cv::Matx<double, 24, 8> image_from_corners;  // d(image) / d(corners x0, y0, ...).
  cv::Matx<double, 8, 8> covariance;           // The four corners', px^2.
  // How the four corners move when the tag grows about its centre (px, each
  // corner away from it; the tone curve and blur are the frame's, shared by
  // every tag). `covariance` already holds the growth within the tag; a
  // shift of the whole image moves them as kQuadShiftX and kQuadShiftY.
  cv::Vec<double, 8> grow;
};

// Errors the tags of one frame share, which a board's pose cannot average
// away (added between tags; each tag's covariance holds them within it): a
// shift of the whole image (the camera's sampling, the lens model's
// remaining error), standard deviation per axis in px; and the share of
// each tag's growth (kCornerNoise.grow_px: the frame's tone curve and blur)
// that every other tag shares. Set on the calibration benchmark's board
// views (calib_comparison, 10 trials): with tags taken as independent, 73 %
// of board poses fell inside their 95 % ellipsoid, the lateral position
// erring most.
inline constexpr double kFrameShiftPx = 0.01;
inline constexpr double kSharedGrowShare = 0.5;

// The corner noise model (kCornerNoise) was fitted on the camera set's
// tags, in hard conditions; a board's many tags measure the noise of their
// own frame in the fit's residuals. With kMinTagsToLowerNoise tags or more,
// residuals under the 5 % point of what the model expects lower the pose's
// covariance in their proportion, to no less than kLowestNoiseScale of it
// (the upper 5 % point raises it: PoseCovariance): what the tags
// share (the tone curve, the lens model, the frame's blur) the pose absorbs
// and the residuals do not show. On the calibration benchmark's board views
// (calib_comparison, 10 trials, seeds 1 to 3) the residuals' median was
// 0.14 of the model's; without the lowering, the spread of error over sigma
// was 0.41-0.61 per axis with every pose inside its 95 % ellipsoid; with it,
// 0.76-1.06 and 96-97 %.
inline constexpr size_t kMinTagsToLowerNoise = 6;
inline constexpr double kLowestNoiseScale = 0.25;

// Standard deviation per coordinate given to the corners of a detection
// that carries no covariance (one made by hand), px. As with any
// covariance, residuals larger than it explains scale the pose's up.
inline constexpr double kUnknownCornerSigmaPx = 0.5;

// The CornerNoise of `detection` (its twelve ring corners, undistorted, as
// `image`; `object` as given). The covariance is the detection's, or
// kUnknownCornerSigmaPx independent when it carries none. False when a
// corner is not finite or beyond the lens model's range.
bool TagCornerNoise(const Detection& detection, const CameraIntrinsics& camera,
                    std::vector<cv::Point3d> object, CornerNoise* noise);

// The covariance of the pose `fit` fitted to the tags of `noise`, in ROS's
// PoseWithCovariance order and units: translation x, y, z (m) then a small
// rotation about the camera's x, y, z axes composed onto the fitted one
// (R' = exp([w]x) R, the body turning about its own origin; rad). The
// corners' covariance carried through the least-squares fit, scaled up
// when the fit's residuals are larger than that noise explains; when
// `rival` (another local solution, or null) fits the corners nearly as
// well, its difference from `fit` is added in the share the corners give
// it.
cv::Matx66d PoseCovariance(const std::vector<const CornerNoise*>& noise, const PoseFit& fit,
                           const PoseFit* rival, const cv::Matx33d& k);

// Two refined solutions closer than this (radians) are one.
inline constexpr double kSameSolutionRadians = 1e-4;

// The best solution among `fits` (sorted best first) that differs from the
// first, or null.
const PoseFit* Rival(const std::vector<PoseFit>& fits);

// The ambiguity of the best of `fits` (sorted best first): its rms over that
// of the best solution that differs from it (as AprilTag 3's err1 / err2);
// 0 when no other solution differs.
double Ambiguity(const std::vector<PoseFit>& fits);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_POSE_FIT_H_
