// IntrinsicsForFrame (camera.h): a camera file's intrinsics for frames of
// another size than the one it was calibrated at.
#include <cmath>

#include "chromatag/detector/camera.h"

namespace chromatag {

std::optional<CameraIntrinsics> IntrinsicsForFrame(const CameraIntrinsics& camera,
                                                   cv::Size calibrated, cv::Size frame) {
  if (frame == calibrated) return camera;
  if (calibrated.empty() || frame.empty()) return std::nullopt;
  const double sx = static_cast<double>(frame.width) / calibrated.width;
  const double sy = static_cast<double>(frame.height) / calibrated.height;
  if (!(std::abs(sx / sy - 1.0) < 0.005)) return std::nullopt;
  CameraIntrinsics scaled = camera;
  scaled.fx *= sx;
  scaled.fy *= sy;
  scaled.cx = (camera.cx + 0.5) * sx - 0.5;
  scaled.cy = (camera.cy + 0.5) * sy - 0.5;
  return scaled;
}

}  // namespace chromatag
