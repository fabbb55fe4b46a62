#include <gtest/gtest.h>

#include "chromatag/detector/camera.h"

namespace chromatag {
namespace {

CameraIntrinsics Camera() {
  CameraIntrinsics camera;
  camera.fx = 1400.0;
  camera.fy = 1390.0;
  camera.cx = 959.5;
  camera.cy = 539.5;
  camera.distortion = {-0.12, 0.05, 0.001, -0.002};
  return camera;
}

TEST(IntrinsicsForFrameTest, SameSizeIsUnchanged) {
  const auto same = IntrinsicsForFrame(Camera(), {1920, 1080}, {1920, 1080});
  ASSERT_TRUE(same);
  EXPECT_EQ(same->fx, 1400.0);
  EXPECT_EQ(same->cx, 959.5);
}

TEST(IntrinsicsForFrameTest, HalfSizeScalesAboutPixelEdges) {
  const auto half = IntrinsicsForFrame(Camera(), {1920, 1080}, {960, 540});
  ASSERT_TRUE(half);
  EXPECT_DOUBLE_EQ(half->fx, 700.0);
  EXPECT_DOUBLE_EQ(half->fy, 695.0);
  // The centre of a 1920-wide frame (959.5) is the centre of a 960-wide one.
  EXPECT_DOUBLE_EQ(half->cx, 479.5);
  EXPECT_DOUBLE_EQ(half->cy, 269.5);
  EXPECT_EQ(half->distortion, Camera().distortion);
  EXPECT_EQ(half->model, Camera().model);
}

TEST(IntrinsicsForFrameTest, NearlyTheSameAspectScales) {
  // 1280 x 721 is within 0.5 % of 16:9.
  EXPECT_TRUE(IntrinsicsForFrame(Camera(), {1920, 1080}, {1280, 721}));
}

TEST(IntrinsicsForFrameTest, AnotherShapeHasNone) {
  EXPECT_FALSE(IntrinsicsForFrame(Camera(), {1920, 1080}, {640, 480}));
  EXPECT_FALSE(IntrinsicsForFrame(Camera(), {1920, 1080}, {1080, 1920}));
  EXPECT_FALSE(IntrinsicsForFrame(Camera(), {1920, 1080}, {0, 0}));
}

}  // namespace
}  // namespace chromatag
