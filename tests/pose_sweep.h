// A rendered sweep for pose over time: a small tag turning slowly in front
// of the camera through noise and blur, detected frame by frame. Shared by
// pose_filter_test and the figure in docs/pose.md
// (scripts/figures/make_pose_smoothing_figure.cc).
#ifndef CHROMATAG_TESTS_POSE_SWEEP_H_
#define CHROMATAG_TESTS_POSE_SWEEP_H_

#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"

namespace chromatag::testing {

inline constexpr double kPoseSweepFps = 30.0;

struct PoseSweep {
  std::vector<cv::Matx33d> rotation;  // The truth, camera_from_tag, per frame.
  std::vector<cv::Vec3d> translation;
  std::vector<bool> found;  // Whether the detector found the tag with a pose.
  std::vector<TagPose> seen;
};

// `frames` frames at kPoseSweepFps of a 40 px 16h5 tag (ID 3) 15 tag sizes
// from a 600 px camera (tag size 1), tilted 4 to 24 degrees and back about
// a turning axis and turning 30 degrees in its plane: small and near face-on,
// where a single frame's tilt is least sure. Noise of 5 grey levels, a blur
// of 0.8 px in linear light.
PoseSweep RenderPoseSweep(int frames);

// The error of (rvec, tvec) against the truth in TagPose::covariance's
// terms: the translation's (truth - estimate), the rotation w with
// R_truth = exp([w]x) R.
cv::Vec3d RotationError(const cv::Vec3d& rvec, const cv::Matx33d& truth);

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_POSE_SWEEP_H_
