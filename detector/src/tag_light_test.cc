#include "tag_light.h"

#include <gtest/gtest.h>

#include <cmath>

#include "chromatag/families/color.h"

namespace chromatag::internal {
namespace {

// A card of paper white and one colour photographed under `gain` (linear R,
// G, B) at `exposure`: 8-bit BGR, white on the left half.
cv::Mat CardUnderLight(const Lab& colour, const Rgb& gain, double exposure) {
  cv::Mat image(20, 40, CV_8UC3);
  const Rgb paper = XyzToLinearRgb(LabToXyz({95, 0, 0}));
  const Rgb ink = XyzToLinearRgb(LabToXyz(colour));
  for (int x = 0; x < image.cols; ++x) {
    const Rgb& lin = x < 20 ? paper : ink;
    const Rgb seen{std::min(1.0, lin.r * gain.r * exposure),
                   std::min(1.0, lin.g * gain.g * exposure),
                   std::min(1.0, lin.b * gain.b * exposure)};
    const Rgb8 c = ToRgb8(LinearToSrgb(seen));
    for (int y = 0; y < image.rows; ++y) image.at<cv::Vec3b>(y, x) = {c.b, c.g, c.r};
  }
  return image;
}

// Under a cast and dim light the colour's own CIELAB is far off; judged
// against the card's white it comes back to within the 8 bits' rounding.
TEST(TagLightTest, ColoursInTheLightOfTheirWhiteLoseTheCast) {
  const Lab red{45, 32, 5};
  const Rgb casts[] = {{0.6, 1, 0.6}, {1.5, 1, 1.5}, {0.64, 1, 1}, {1, 0.72, 0.42}};
  for (const Rgb& gain : casts) {
    // 0.6: the brightest a gain of 1.5 leaves unclipped.
    for (double exposure : {0.6, 0.35}) {
      const cv::Mat card = CardUnderLight(red, gain, exposure);
      const ImageView view(card, PixelOrder::kBgr, ColorTable::Get());
      TagLight light;
      EXPECT_FALSE(light.Settle());
      light.AddWhite(view, {5, 10});
      light.AddWhite(view, {12, 4});
      light.AddWhite(view, {30, 10});  // A reading off the white: the median ignores it.
      ASSERT_TRUE(light.Settle());
      const LabF as_shot = view.Lab(30, 10);
      const LabF balanced = light.BalancedAt(view, {30, 10});
      EXPECT_NEAR(balanced.L, red.L, 1.5) << gain.r << " " << gain.b << " x" << exposure;
      EXPECT_NEAR(balanced.a, red.a, 2.0) << gain.r << " " << gain.b << " x" << exposure;
      EXPECT_NEAR(balanced.b, red.b, 2.0) << gain.r << " " << gain.b << " x" << exposure;
      EXPECT_GT(std::hypot(as_shot.L - red.L, as_shot.a - red.a, as_shot.b - red.b), 6.0)
          << gain.r << " " << gain.b << " x" << exposure;
    }
  }
}

// A reading that is black, not a quiet zone, gives no light to judge by.
TEST(TagLightTest, ABlackWhiteDoesNotSettle) {
  const cv::Mat black(5, 5, CV_8UC3, cv::Scalar(0, 0, 0));
  const ImageView view(black, PixelOrder::kBgr, ColorTable::Get());
  TagLight light;
  light.AddWhite(view, {2, 2});
  EXPECT_FALSE(light.Settle());
  EXPECT_FALSE(light.settled());
}

}  // namespace
}  // namespace chromatag::internal
