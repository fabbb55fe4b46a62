// Tag pose from a detection (spec section 7).
#ifndef CHROMATAG_DETECTOR_POSE_H_
#define CHROMATAG_DETECTOR_POSE_H_

#include <string>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

// camera_from_tag for a decoded detection: OpenCV's solvePnP with
// SOLVEPNP_IPPE_SQUARE on the four outer corners (which picks the right one
// of the two planar solutions), then Levenberg-Marquardt over all twelve
// ring corners (outer, green/black, red/green). `tag_size` is the side of the
// black square in metres. False (and *error) for invalid intrinsics, a
// non-positive size or a detection without a family.
bool EstimateTagPose(const Detection& detection, const CameraIntrinsics& camera, double tag_size,
                     TagPose* pose, std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_POSE_H_
