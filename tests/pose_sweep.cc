#include "pose_sweep.h"

#include <cmath>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/detector.h"
#include "synthetic_scene.h"

namespace chromatag::testing {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

PoseSweep RenderPoseSweep(int frames) {
  PoseSweep sweep;
  SceneTag tag;
  tag.id = 3;
  tag.black_square_px = 40;
  tag.distance = 15;
  SceneOptions options;
  options.width = options.height = 240;
  options.noise_sigma = 5;
  options.blur_sigma = 0.8;
  options.blur_in_linear_light = true;
  const cv::Point2d principal(options.width / 2.0, options.height / 2.0);
  tag.centre = principal;
  const auto detector = Detector::Create(PoseOptionsFor(tag, principal));
  for (int f = 0; f < frames; ++f) {
    const double s = f / std::max(1.0, frames - 1.0);
    tag.tilt_deg = 14 - 10 * std::cos(2 * kPi * s);
    tag.tilt_axis_deg = 20 + 60 * s;
    tag.rotation_deg = 30 * s;
    options.seed = static_cast<unsigned>(f + 1);
    const Scene scene = RenderScene({tag}, options);
    // The truth, as the scene turns the tag plane (u right, v down); the tag
    // frame has y up and z towards the camera.
    const double a = tag.tilt_axis_deg * kPi / 180;
    cv::Matx33d tilt, spin;
    cv::Rodrigues(cv::Vec3d(std::cos(a), std::sin(a), 0) * (tag.tilt_deg * kPi / 180), tilt);
    cv::Rodrigues(cv::Vec3d(0, 0, tag.rotation_deg * kPi / 180), spin);
    sweep.rotation.push_back(tilt * spin * cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, -1));
    sweep.translation.emplace_back(0, 0, tag.distance);
    const DetectionResult result = detector->Detect(scene.bgr);
    const bool found = result.detections.size() == 1 && result.detections[0].has_pose;
    sweep.found.push_back(found);
    sweep.seen.push_back(found ? result.detections[0].pose : TagPose());
  }
  return sweep;
}

cv::Vec3d RotationError(const cv::Vec3d& rvec, const cv::Matx33d& truth) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  cv::Vec3d w;
  cv::Rodrigues(cv::Matx33d(truth * r.t()), w);
  return w;
}

}  // namespace chromatag::testing
