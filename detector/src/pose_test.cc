// The pose covariance against Monte Carlo: corners moved by known noise,
// the pose fitted again and again, its errors compared with what
// TagPose::covariance and BoardPose::covariance predict.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/camera.h"
#include "chromatag/detector/pose.h"

#include "geometry.h"

namespace chromatag {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The 95 % point of a chi-square with six degrees of freedom.
constexpr double kChi2Six95 = 12.5916;

CameraIntrinsics Camera() {
  CameraIntrinsics camera;
  camera.fx = camera.fy = 600;
  camera.cx = 376;
  camera.cy = 240;
  return camera;
}

cv::Matx33d Rotation(const cv::Vec3d& rvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  return r;
}

// A detection of a 16h5 tag of side `size` placed by camera_from_tag (r, t),
// made as the detector makes one: its four outer corners seen with
// Gaussian noise of `sigma` px per coordinate (and that covariance), the
// inner corners placed from them through the square's homography.
Detection Seen(const cv::Matx33d& r, const cv::Vec3d& t, double size,
               const CameraIntrinsics& camera, double sigma, std::mt19937* rng) {
  static const auto family = TagFamily::Load("16h5");
  Detection d;
  d.family = family.get();
  d.id = family->kept_ids()[0];
  std::normal_distribution<double> gauss(0.0, std::max(sigma, 1e-12));
  const double h = 0.5 * size;
  const cv::Vec3d square[4] = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  for (int i = 0; i < 4; ++i) {
    const cv::Vec3d p = r * square[i] + t;
    d.corners[i] =
        ProjectPoints(camera, {cv::Point3d(p[0], p[1], p[2])}, cv::Vec3d(), cv::Vec3d())[0];
    if (sigma > 0) d.corners[i] += cv::Point2d(gauss(*rng), gauss(*rng));
  }
  d.image_from_tag = internal::UnitSquareToQuad(d.corners);
  const int cells = family->black_square_cells();
  d.green_corners = internal::InsetSquare(d.image_from_tag, 1.0 / cells);
  d.red_corners = internal::InsetSquare(d.image_from_tag, 2.0 / cells);
  d.corner_covariance = sigma * sigma * cv::Matx<double, 8, 8>::eye();
  return d;
}

// The error of (rvec, tvec) against the truth in the covariance's order and
// frame: truth - estimate for the translation, then the rotation w with
// R_truth = exp([w]x) R_estimate.
cv::Vec6d Error(const cv::Vec3d& rvec, const cv::Vec3d& tvec, const cv::Matx33d& r,
                const cv::Vec3d& t) {
  cv::Vec3d w;
  cv::Rodrigues(cv::Matx33d(r * Rotation(rvec).t()), w);
  const cv::Vec3d dt = t - tvec;
  return {dt[0], dt[1], dt[2], w[0], w[1], w[2]};
}

// Over many fits: each axis's error over its predicted sigma (the spread
// of that ratio), and the share of errors inside the 95 % ellipsoid.
struct Calibration {
  std::vector<double> spread = std::vector<double>(6, 0.0);
  double coverage = 0.0;
};

struct Sums {
  std::vector<double> squares = std::vector<double>(6, 0.0);
  int inside = 0, count = 0;
  void Add(const cv::Vec6d& error, const cv::Matx66d& covariance) {
    for (int i = 0; i < 6; ++i) squares[i] += error[i] * error[i] / covariance(i, i);
    const double nees = (error.t() * covariance.inv(cv::DECOMP_CHOLESKY) * error)[0];
    inside += nees <= kChi2Six95;
    ++count;
  }
  Calibration Result() const {
    Calibration c;
    for (int i = 0; i < 6; ++i) c.spread[i] = std::sqrt(squares[i] / count);
    c.coverage = static_cast<double>(inside) / count;
    return c;
  }
};

Calibration TagTrials(const cv::Vec3d& rvec, const cv::Vec3d& t, double size, double sigma,
                      int trials) {
  const CameraIntrinsics camera = Camera();
  const cv::Matx33d r = Rotation(rvec);
  std::mt19937 rng(7);
  Sums sums;
  for (int trial = 0; trial < trials; ++trial) {
    const Detection d = Seen(r, t, size, camera, sigma, &rng);
    TagPose pose;
    if (!EstimateTagPose(d, camera, size, &pose)) continue;
    sums.Add(Error(pose.rvec, pose.tvec, r, t), pose.covariance);
  }
  EXPECT_GT(sums.count, trials * 9 / 10);
  return sums.Result();
}

TEST(PoseCovarianceTest, TiltedTagErrorsFollowThePredictedSpread) {
  // 60 mm at 0.6 m, 40 degrees of tilt: about 60 px across, one solution.
  const Calibration c =
      TagTrials({40 * kPi / 180, 10 * kPi / 180, 0.2}, {0.05, -0.02, 0.6}, 0.06, 0.3, 2000);
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(c.spread[i], 0.85) << "axis " << i;
    EXPECT_LT(c.spread[i], 1.15) << "axis " << i;
  }
  EXPECT_GT(c.coverage, 0.93);
  EXPECT_LT(c.coverage, 0.97);
}

TEST(PoseCovarianceTest, NearlyFrontalSmallTagCoversItsFlips) {
  // 30 px across, 8 degrees of tilt, 0.5 px noise: the mirrored tilt fits
  // about as well in many trials, and some fits pick it; the covariance
  // must still hold the truth about as often as it says.
  const Calibration c = TagTrials({8 * kPi / 180, 0, 0}, {0, 0, 1.0}, 0.05, 0.5, 2000);
  EXPECT_GT(c.coverage, 0.9);
  // Not covered by a covariance blown up past use either.
  EXPECT_LT(c.coverage, 0.995);
}

TEST(PoseCovarianceTest, ScalesWithTheCornersNoiseAndIsSymmetric) {
  const CameraIntrinsics camera = Camera();
  // 57 degrees of tilt, 100 px across: the mirrored tilt fits far worse,
  // so the covariance is the corners' carried through the fit alone.
  const cv::Matx33d r = Rotation({1.0, 0.1, 0});
  std::mt19937 rng(3);
  Detection d = Seen(r, {0, 0, 0.5}, 0.08, camera, 0.0, &rng);
  d.corner_covariance = 0.04 * cv::Matx<double, 8, 8>::eye();
  TagPose a, b;
  ASSERT_TRUE(EstimateTagPose(d, camera, 0.08, &a));
  d.corner_covariance *= 4.0;
  ASSERT_TRUE(EstimateTagPose(d, camera, 0.08, &b));
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(a.covariance(i, i), 0.0);
    EXPECT_NEAR(b.covariance(i, i), 4.0 * a.covariance(i, i), 1e-6 * b.covariance(i, i));
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(a.covariance(i, j), a.covariance(j, i), 1e-9 * a.covariance(i, i) + 1e-18);
  }
  // Depth is the worst-known axis of a small tag seen from afar.
  EXPECT_GT(a.covariance(2, 2), a.covariance(0, 0));
}

TEST(PoseCovarianceTest, ADetectionMadeByHandGetsAnAssumedCornerNoise) {
  const CameraIntrinsics camera = Camera();
  std::mt19937 rng(3);
  Detection d = Seen(Rotation({0.6, 0.1, 0}), {0, 0, 0.8}, 0.08, camera, 0.0, &rng);
  TagPose assumed, given;
  d.corner_covariance = cv::Matx<double, 8, 8>::zeros();
  ASSERT_TRUE(EstimateTagPose(d, camera, 0.08, &assumed));
  d.corner_covariance = 0.25 * cv::Matx<double, 8, 8>::eye();  // 0.5 px.
  ASSERT_TRUE(EstimateTagPose(d, camera, 0.08, &given));
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(assumed.covariance(i, i), given.covariance(i, i), 1e-6 * given.covariance(i, i));
}

TEST(PoseCovarianceTest, BoardErrorsFollowThePredictedSpread) {
  // A 3 x 2 grid of 40 mm tags, 60 mm apart, at 0.9 m and 30 degrees.
  const auto family = TagFamily::Load("16h5");
  Board board;
  for (int i = 0; i < 6; ++i) {
    BoardTag tag;
    tag.family = "16h5";
    tag.id = family->kept_ids()[i];
    tag.size = 0.04;
    tag.translation = {((i % 3) - 1) * 0.06, (0.5 - (i / 3)) * 0.06, 0};
    board.tags.push_back(tag);
  }
  const CameraIntrinsics camera = Camera();
  const cv::Matx33d r = Rotation({30 * kPi / 180, -15 * kPi / 180, 0.1});
  const cv::Vec3d t(-0.03, 0.02, 0.9);
  std::mt19937 rng(11);
  Sums sums;
  for (int trial = 0; trial < 1000; ++trial) {
    std::vector<Detection> detections;
    for (const BoardTag& tag : board.tags) {
      Detection d = Seen(r * tag.rotation, r * tag.translation + t, tag.size, camera, 0.3, &rng);
      d.id = tag.id;
      detections.push_back(d);
    }
    BoardPose pose;
    ASSERT_TRUE(EstimateBoardPose(detections, board, camera, &pose));
    sums.Add(Error(pose.rvec, pose.tvec, r, t), pose.covariance);
  }
  const Calibration c = sums.Result();
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(c.spread[i], 0.85) << "axis " << i;
    EXPECT_LT(c.spread[i], 1.15) << "axis " << i;
  }
  EXPECT_GT(c.coverage, 0.93);
  EXPECT_LT(c.coverage, 0.97);
}

}  // namespace
}  // namespace chromatag
