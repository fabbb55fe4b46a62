#include "image_view.h"

#include <gtest/gtest.h>

#include <random>

namespace chromatag::internal {
namespace {

// SampleLine (eight samples at a time with AVX2 where it can) gives exactly
// what Sample gives point by point, for both channels the detector uses, on
// lines anywhere in the frame including along its last rows and columns,
// and refuses lines that leave it.
TEST(ImageViewTest, SampleLineMatchesSamplePointByPoint) {
  std::mt19937 rng(7);
  cv::Mat image(61, 83, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(256));
  for (PixelOrder order : {PixelOrder::kBgr, PixelOrder::kRgb}) {
    const ImageView view(image, order, ColorTable::Get());
    std::uniform_real_distribution<float> px(-2.f, 85.f), py(-2.f, 63.f), step(-0.9f, 0.9f);
    int inside = 0;
    for (int trial = 0; trial < 4000; ++trial) {
      const float x = px(rng), y = py(rng), dx = step(rng), dy = step(rng);
      const int n = 1 + trial % 17;
      for (const ChannelWeights& w : {kGray, kRedMinusGreen, ChannelWeights{2, 0, -1}}) {
        float line[17];
        const bool ok = view.SampleLine(x, y, dx, dy, n, w, line);
        bool all = true;
        float point[17];
        for (int i = 0; i < n; ++i)
          all &= view.Sample(x + static_cast<float>(i) * dx, y + static_cast<float>(i) * dy, w,
                             &point[i]);
        ASSERT_EQ(ok, all) << "trial " << trial;
        if (!ok) continue;
        ++inside;
        for (int i = 0; i < n; ++i) ASSERT_EQ(line[i], point[i]) << "trial " << trial << " i " << i;
      }
    }
    EXPECT_GT(inside, 3000);  // Most lines lie inside: the comparison was made.
  }
}

}  // namespace
}  // namespace chromatag::internal
