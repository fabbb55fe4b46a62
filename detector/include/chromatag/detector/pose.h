// Tag pose from a detection (spec section 7).
#ifndef CHROMATAG_DETECTOR_POSE_H_
#define CHROMATAG_DETECTOR_POSE_H_

#include <string>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

// camera_from_tag for a decoded detection: both planar solutions of the four
// outer corners (OpenCV's SOLVEPNP_IPPE_SQUARE), each refined by
// Levenberg-Marquardt over all twelve ring corners (outer, green/black,
// red/green) in small rotations composed onto the estimate (no singularity at
// any view, frontal included), and the one with the smaller reprojection
// error kept (TagPose::ambiguity compares the two). The rotation vector's
// norm is at most pi. `tag_size` is the side of the black square in metres.
// False (and *error) for invalid intrinsics, a non-positive size, a
// detection without a family or with non-finite corners, or no pose with the
// tag in front of the camera.
bool EstimateTagPose(const Detection& detection, const CameraIntrinsics& camera, double tag_size,
                     TagPose* pose, std::string* error = nullptr);

// One figure each for how far a pose's translation and rotation can be
// trusted: the root of the trace of the covariance's translation block
// (metres) and of its rotation block (radians), in TagPose::covariance's
// layout (BoardPose's too). The root mean square length of the error each
// part is expected to have: about 1.6 times a single axis's sigma when the
// three are alike.
struct PoseSigma {
  double translation = 0.0;
  double rotation = 0.0;
};
PoseSigma SigmaOf(const cv::Matx66d& covariance);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_POSE_H_
