#include "chromatag/detector/pose_filter.h"

#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>

namespace chromatag {
namespace {

// Before the second frame the velocity is not known: a prior of a metre and
// a half-turn a second.
constexpr double kVelocityPrior = 0.5;
constexpr double kAngularVelocityPrior = 1.0;

cv::Matx33d Exp(const cv::Vec3d& w) {
  cv::Matx33d r;
  cv::Rodrigues(w, r);
  return r;
}

cv::Vec3d Log(const cv::Matx33d& r) {
  cv::Vec3d w;
  cv::Rodrigues(r, w);
  return w;
}

// `covariance` when it is a positive definite covariance, else one that
// says nothing (a metre and a radian on each axis).
cv::Matx66d Usable(const cv::Matx66d& covariance) {
  cv::Matx66d inverse;
  bool finite = true;
  for (double v : covariance.val) finite &= std::isfinite(v);
  if (finite && cv::invert(covariance, inverse, cv::DECOMP_CHOLESKY) != 0.0) return covariance;
  return cv::Matx66d::eye();
}

// The squared Mahalanobis distance of `v` under `s`; infinite when `s` is
// not positive definite.
double Mahalanobis(const cv::Vec6d& v, const cv::Matx66d& s) {
  cv::Matx66d inverse;
  if (cv::invert(s, inverse, cv::DECOMP_CHOLESKY) == 0.0)
    return std::numeric_limits<double>::infinity();
  return (v.t() * inverse * v)[0];
}

// The difference of pose b from pose a in the covariance's terms.
cv::Vec6d Difference(const cv::Matx33d& ra, const cv::Vec3d& ta, const cv::Matx33d& rb,
                     const cv::Vec3d& tb) {
  const cv::Vec3d t = tb - ta, w = Log(rb * ra.t());
  return {t[0], t[1], t[2], w[0], w[1], w[2]};
}

}  // namespace

bool PoseFilterOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(translation_acceleration > 0) || !std::isfinite(translation_acceleration) ||
      !(rotation_acceleration > 0) || !std::isfinite(rotation_acceleration))
    return fail(
        "translation_acceleration and rotation_acceleration must be positive and finite (m/s and "
        "rad/s a second)");
  if (!(gate_chi2 > 0) || !std::isfinite(gate_chi2))
    return fail("gate_chi2 must be positive and finite (a squared Mahalanobis distance)");
  if (frames_to_jump < 1) return fail("frames_to_jump must be 1 or more");
  if (!(max_gap_s > 0) || !std::isfinite(max_gap_s))
    return fail("max_gap_s must be positive and finite (seconds)");
  return true;
}

PoseFilter::PoseFilter(const PoseFilterOptions& options) : options_(options) {}

void PoseFilter::Reset() {
  started_ = false;
  left_out_ = 0;
}

void PoseFilter::Start(double time_s, const cv::Matx33d& rotation, const cv::Vec3d& translation,
                       const cv::Matx66d& covariance) {
  started_ = true;
  time_s_ = time_s;
  rotation_ = rotation;
  translation_ = translation;
  velocity_ = angular_velocity_ = cv::Vec3d(0, 0, 0);
  p_ = Matx12::zeros();
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) p_(i, j) = covariance(i, j);
  for (int i = 0; i < 3; ++i) {
    p_(6 + i, 6 + i) = kVelocityPrior * kVelocityPrior;
    p_(9 + i, 9 + i) = kAngularVelocityPrior * kAngularVelocityPrior;
  }
  left_out_ = 0;
}

FilteredPose PoseFilter::Output(bool used, bool restarted) const {
  FilteredPose out;
  out.rvec = Log(rotation_);
  out.tvec = translation_;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) out.covariance(i, j) = 0.5 * (p_(i, j) + p_(j, i));
  out.used = used;
  out.restarted = restarted;
  return out;
}

void PoseFilter::Predict(double dt) {
  // The pose moves at its velocities; white noise on the accelerations
  // widens it (per axis [dt^3/3 dt^2/2; dt^2/2 dt] q).
  translation_ += velocity_ * dt;
  rotation_ = Exp(angular_velocity_ * dt) * rotation_;
  Matx12 f = Matx12::eye();
  for (int i = 0; i < 6; ++i) f(i, 6 + i) = dt;
  p_ = f * p_ * f.t();
  for (int i = 0; i < 6; ++i) {
    const double a = i < 3 ? options_.translation_acceleration : options_.rotation_acceleration;
    const double q = a * a;
    p_(i, i) += q * dt * dt * dt / 3;
    p_(i, 6 + i) += q * dt * dt / 2;
    p_(6 + i, i) += q * dt * dt / 2;
    p_(6 + i, 6 + i) += q * dt;
  }
}

void PoseFilter::Correct(const cv::Vec6d& innovation, const cv::Matx66d& s,
                         const cv::Matx66d& seen) {
  // K = P H^T S^-1 with H = [I 0]; Joseph's form keeps P symmetric.
  cv::Matx66d s_inverse;
  cv::invert(s, s_inverse, cv::DECOMP_CHOLESKY);
  cv::Matx<double, 12, 6> p_h;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 6; ++j) p_h(i, j) = p_(i, j);
  const cv::Matx<double, 12, 6> k = p_h * s_inverse;
  const Vec12 correction = k * innovation;
  translation_ += cv::Vec3d(correction[0], correction[1], correction[2]);
  rotation_ = Exp(cv::Vec3d(correction[3], correction[4], correction[5])) * rotation_;
  velocity_ += cv::Vec3d(correction[6], correction[7], correction[8]);
  angular_velocity_ += cv::Vec3d(correction[9], correction[10], correction[11]);
  Matx12 i_kh = Matx12::eye();
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 6; ++j) i_kh(i, j) -= k(i, j);
  p_ = i_kh * p_ * i_kh.t() + k * seen * k.t();
}

FilteredPose PoseFilter::Update(double time_s, const cv::Vec3d& rvec, const cv::Vec3d& tvec,
                                const cv::Matx66d& covariance) {
  // The frame's translation and rotation covariances, without their
  // correlation: the planar ambiguity's share ties the two along the
  // mirrored tilt, and a filter that followed it would move the position
  // with every doubtful tilt (on pose_filter_test's sweep, with the
  // correlation kept, the translation's jitter fell to 0.73 of each frame's
  // own instead of 0.43, when last measured).
  cv::Matx66d seen = Usable(covariance);
  for (int i = 0; i < 3; ++i) {
    for (int j = 3; j < 6; ++j) seen(i, j) = seen(j, i) = 0.0;
  }
  const cv::Matx33d rotation = Exp(rvec);
  const double dt = time_s - time_s_;
  if (!started_ || !(dt > 0) || dt > options_.max_gap_s) {
    Start(time_s, rotation, tvec, seen);
    return Output(true, true);
  }
  Predict(dt);
  time_s_ = time_s;
  // The frame against the prediction.
  const cv::Vec6d innovation = Difference(rotation_, translation_, rotation, tvec);
  cv::Matx66d s = seen;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) s(i, j) += p_(i, j);
  if (Mahalanobis(innovation, s) <= options_.gate_chi2) {
    left_out_ = 0;
    Correct(innovation, s, seen);
    return Output(true, false);
  }
  // Left out; several in a row that agree with each other are a move.
  const bool agrees =
      left_out_ > 0 &&
      Mahalanobis(Difference(left_out_rotation_, left_out_translation_, rotation, tvec),
                  left_out_covariance_ + seen) <= options_.gate_chi2;
  left_out_ = agrees ? left_out_ + 1 : 1;
  left_out_rotation_ = rotation;
  left_out_translation_ = tvec;
  left_out_covariance_ = seen;
  if (left_out_ >= options_.frames_to_jump) {
    Start(time_s, rotation, tvec, seen);
    return Output(true, true);
  }
  return Output(false, false);
}

}  // namespace chromatag
