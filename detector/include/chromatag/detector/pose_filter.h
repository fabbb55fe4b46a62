// A tag's or board's pose over frames: each frame's pose (TagPose or
// BoardPose, with its covariance) weighed by how far it can be trusted, in a
// Kalman filter that lets the pose move at a constant velocity give or take
// how fast it may change. A frame far from where the pose should be, by its
// covariance and the filter's (the mirrored tilt a small or face-on tag
// sometimes gives), is left out; only when several frames in a row agree
// with each other there is the pose taken to have moved (docs/pose.md,
// "Pose over time").
#ifndef CHROMATAG_DETECTOR_POSE_FILTER_H_
#define CHROMATAG_DETECTOR_POSE_FILTER_H_

#include <string>

#include <opencv2/core.hpp>

namespace chromatag {

struct PoseFilterOptions {
  // How fast the motion itself may change, as the standard deviation of the
  // velocity's change over a second: metres per second and radians per
  // second, per second. The defaults suit slow, smooth motion (a robot arm,
  // a walking pace, a tag turning at 10 degrees a second); a hand-held
  // camera moves faster (0.5 m/s and 2 rad/s a second): with the defaults,
  // its quick turns are left out and then jumped to. On the rendered sweep
  // of PoseFilterTest a rotation acceleration of 0.08 to 0.09 smooths most
  // (0.05 lags behind the sweep's turns, 0.15 follows the frames' jitter).
  double translation_acceleration = 0.05;
  double rotation_acceleration = 0.08;
  // A frame whose pose lies further from the prediction than this squared
  // Mahalanobis distance (the two covariances added; chi-square with six
  // degrees of freedom: 22.46 is its 99.9 % point) is left out...
  double gate_chi2 = 22.46;
  // ...unless this many frames in a row are left out and agree with each
  // other (each within the gate of the one before): then the pose moved
  // (a jump, or the other planar solution is the true one) and the filter
  // starts again from the last of them.
  int frames_to_jump = 5;
  // More than this many seconds without a frame: the filter starts again.
  double max_gap_s = 1.0;

  bool IsValid(std::string* error = nullptr) const;
};

// The filter's pose after a frame, in TagPose's terms.
struct FilteredPose {
  cv::Vec3d rvec;  // Rodrigues rotation; norm at most pi.
  cv::Vec3d tvec;
  // In TagPose::covariance's order and units (ROS's).
  cv::Matx66d covariance = cv::Matx66d::zeros();
  // Whether the frame's pose was used, or left out as too far from the
  // prediction (the filter then reports its prediction).
  bool used = true;
  // Whether the filter (re)started at this frame: the first frame, after a
  // gap, or a jump.
  bool restarted = false;
};

class PoseFilter {
 public:
  explicit PoseFilter(const PoseFilterOptions& options = {});

  // Feeds one frame's pose seen at `time_s` (seconds, increasing; a frame
  // at or before the last one restarts the filter) and returns the filtered
  // pose. `covariance` as TagPose::covariance; one that is not positive
  // definite is taken as uninformative (a metre and a radian).
  FilteredPose Update(double time_s, const cv::Vec3d& rvec, const cv::Vec3d& tvec,
                      const cv::Matx66d& covariance);

  // Forgets every frame.
  void Reset();
  bool started() const { return started_; }

 private:
  using Matx12 = cv::Matx<double, 12, 12>;
  using Vec12 = cv::Vec<double, 12>;

  void Start(double time_s, const cv::Matx33d& rotation, const cv::Vec3d& translation,
             const cv::Matx66d& covariance);
  FilteredPose Output(bool used, bool restarted) const;
  // Moves the pose and widens its covariance over `dt` seconds.
  void Predict(double dt);
  // Takes in a frame `innovation` away from the prediction (`s`: its
  // covariance, the frame's `seen` and the prediction's together).
  void Correct(const cv::Vec6d& innovation, const cv::Matx66d& s, const cv::Matx66d& seen);

  PoseFilterOptions options_;
  bool started_ = false;
  double time_s_ = 0.0;
  // The pose, and the error state around it: translation, rotation (as
  // TagPose's covariance), then their velocities.
  cv::Matx33d rotation_ = cv::Matx33d::eye();
  cv::Vec3d translation_;
  cv::Vec3d velocity_, angular_velocity_;
  Matx12 p_ = Matx12::zeros();
  // Frames left out in a row, and the last of them.
  int left_out_ = 0;
  cv::Matx33d left_out_rotation_ = cv::Matx33d::eye();
  cv::Vec3d left_out_translation_;
  cv::Matx66d left_out_covariance_ = cv::Matx66d::zeros();
};

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_POSE_FILTER_H_
