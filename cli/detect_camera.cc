#include "detect_camera.h"

#include <cstdio>

#include "chromatag/detector/camera.h"

namespace chromatag::cli {

const Detector& FrameSizeDetectors::For(cv::Size size, std::string* note) const {
  const auto& camera = detector_.options().camera;
  if (!camera || camera_size_.empty() || size == camera_size_) return detector_;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto key = std::make_pair(size.width, size.height);
  auto found = scaled_.find(key);
  if (found != scaled_.end()) return found->second ? *found->second : detector_;
  const auto intrinsics = IntrinsicsForFrame(*camera, camera_size_, size);
  char text[320];
  std::unique_ptr<Detector> scaled;
  if (intrinsics) {
    DetectorOptions options = detector_.options();
    options.camera = *intrinsics;
    scaled = Detector::Create(options);
    std::snprintf(text, sizeof text,
                  "chromatag detect: warning: the camera file is for %d x %d frames; %d x %d "
                  "frames use its intrinsics scaled by %.4g\n",
                  camera_size_.width, camera_size_.height, size.width, size.height,
                  static_cast<double>(size.width) / camera_size_.width);
  } else {
    std::snprintf(text, sizeof text,
                  "chromatag detect: warning: the camera file is for %d x %d frames; %d x %d "
                  "frames have another shape, and their poses are wrong (calibrate the "
                  "camera at this size)\n",
                  camera_size_.width, camera_size_.height, size.width, size.height);
  }
  *note += text;
  auto& entry = scaled_[key];
  entry = std::move(scaled);
  return entry ? *entry : detector_;
}

}  // namespace chromatag::cli
