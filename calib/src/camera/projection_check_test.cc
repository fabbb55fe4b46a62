#include "projection_check.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chromatag::internal {
namespace {

CameraIntrinsics Lens() {
  CameraIntrinsics camera;
  camera.fx = camera.fy = 1000;
  camera.cx = 641;
  camera.cy = 478;
  camera.distortion = {-0.12, 0.05, 0, 0, 0};
  return camera;
}

const cv::Size kSize(1280, 960), kGrid(24, 18);

double Worst(const std::vector<double>& map) {
  double median = 0, worst = 0;
  CentralFigures(map, kSize, kGrid, &median, &worst);
  return worst;
}

// One model against itself agrees everywhere; a turn of the camera frame is
// the fit's to choose, so a principal point 1.5 px off (nearly a turn)
// leaves far less than 1.5 px; a focal length 0.1 % off, which no turn
// undoes, leaves about that share of the distance from the centre (0.1 %
// of 500 px at the central region's corners).
TEST(CrossValidationMapTest, AlignsTheFramesAndMeasuresWhatIsLeft) {
  const CameraIntrinsics a = Lens();
  EXPECT_LT(Worst(CrossValidationMap(a, a, 0.5, kSize, kGrid)), 1e-6);
  CameraIntrinsics b = a;
  b.cy += 1.5;
  EXPECT_LT(Worst(CrossValidationMap(a, b, 0.5, kSize, kGrid)), 0.3);
  b = a;
  b.fx *= 1.001;
  b.fy *= 1.001;
  const double worst = Worst(CrossValidationMap(a, b, 0.5, kSize, kGrid));
  EXPECT_GT(worst, 0.3);
  EXPECT_LT(worst, 0.8);
}

// The uncertainty map grows with the intrinsics' covariance: four times
// the covariance, twice the uncertainty; none, none.
TEST(UncertaintyMapTest, ScalesWithTheCovariance) {
  const CameraIntrinsics camera = Lens();
  cv::Mat covariance = cv::Mat::zeros(8, 8, CV_64F);
  const std::vector<double> none = UncertaintyMap(camera, covariance, false, 0.5, kSize, kGrid);
  EXPECT_LT(Worst(none), 1e-9);
  covariance.at<double>(0, 0) = covariance.at<double>(1, 1) = 0.25;  // fx, fy: 0.5 px.
  covariance.at<double>(4, 4) = 1e-6;                                // k1: 0.001.
  const std::vector<double> some = UncertaintyMap(camera, covariance, false, 0.5, kSize, kGrid);
  const std::vector<double> more =
      UncertaintyMap(camera, 4.0 * covariance, false, 0.5, kSize, kGrid);
  ASSERT_EQ(some.size(), static_cast<size_t>(kGrid.area()));
  EXPECT_GT(Worst(some), 0.0);
  for (size_t i = 0; i < some.size(); ++i)
    EXPECT_NEAR(more[i], 2.0 * some[i], 1e-9 + 1e-6 * some[i]);
}

}  // namespace
}  // namespace chromatag::internal
