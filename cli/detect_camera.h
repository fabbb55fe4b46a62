// `chromatag detect`'s camera: a camera file's intrinsics are for the image
// size it records. Frames of another size with the same aspect get them
// scaled (IntrinsicsForFrame, detector/camera.h); of another shape, the
// intrinsics as they are, with a warning that their poses are wrong.
#ifndef CHROMATAG_CLI_DETECT_CAMERA_H_
#define CHROMATAG_CLI_DETECT_CAMERA_H_

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>

#include <opencv2/core.hpp>

#include "chromatag/detector/detector.h"

namespace chromatag::cli {

class FrameSizeDetectors {
 public:
  // `camera_size`: the camera file's recorded image size; empty: none
  // recorded, and every frame uses `detector` as it is.
  FrameSizeDetectors(const Detector& detector, cv::Size camera_size)
      : detector_(detector), camera_size_(camera_size) {}

  // The detector for frames of `size`; the first frame of each size other
  // than the camera file's adds its warning to *note. Thread-safe.
  const Detector& For(cv::Size size, std::string* note) const;

 private:
  const Detector& detector_;
  const cv::Size camera_size_;
  mutable std::mutex mutex_;
  // Detectors for frame sizes other than the camera file's; null: not scaled.
  mutable std::map<std::pair<int, int>, std::unique_ptr<Detector>> scaled_;
};

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_DETECT_CAMERA_H_
