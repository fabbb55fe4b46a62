#include "image_view.h"

#include <gtest/gtest.h>

#include <cmath>
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

// FirstNotClearlyAbove (eight steps at a time with AVX2) stops where a loop
// over CoarseA would: at the first pixel outside the frame or not above the
// threshold, including scans that run off any edge and past the frame's
// last pixel, in either channel order.
TEST(ImageViewTest, FirstNotClearlyAboveMatchesAPixelByPixelLoop) {
  std::mt19937 rng(11);
  cv::Mat image(47, 71, CV_8UC3);
  // Mostly red (coarse a* far above the thresholds), with scattered other
  // colours where the scans stop.
  image.setTo(cv::Scalar(30, 40, 220));
  for (int i = 0; i < 120; ++i) {
    cv::Vec3b& p = image.at<cv::Vec3b>(rng() % image.rows, rng() % image.cols);
    p = cv::Vec3b(rng() % 256, rng() % 256, rng() % 256);
  }
  const int directions = 24;
  for (PixelOrder order : {PixelOrder::kBgr, PixelOrder::kRgb}) {
    const ImageView view(image, order, ColorTable::Get());
    std::uniform_real_distribution<float> px(-3.f, 74.f), py(-3.f, 50.f), threshold(-20.f, 70.f);
    int stopped_inside = 0;
    for (int trial = 0; trial < 3000; ++trial) {
      const float x = px(rng), y = py(rng), above = threshold(rng);
      const float angle = 2.f * static_cast<float>(CV_PI) * (trial % directions) / directions;
      const float dx = std::cos(angle), dy = std::sin(angle);
      const int first = trial % 3, last = first + static_cast<int>(rng() % 90);
      int expected = first;
      for (; expected <= last; ++expected) {
        const int ix = RoundToInt(x + static_cast<float>(expected) * dx);
        const int iy = RoundToInt(y + static_cast<float>(expected) * dy);
        if (!view.Contains(ix, iy) || !(static_cast<float>(view.CoarseA(ix, iy)) > above)) break;
      }
      ASSERT_EQ(view.FirstNotClearlyAbove(x, y, dx, dy, first, last, above), expected)
          << "trial " << trial;
      if (expected <= last) ++stopped_inside;
    }
    EXPECT_GT(stopped_inside, 1000);
  }
  // Along the last row, up to the frame's last pixel (a 32-bit read there
  // would pass the buffer's end) and past it: everything is above -200.
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  EXPECT_EQ(view.FirstNotClearlyAbove(55.f, 46.f, 1.f, 0.f, 0, 15, -200.f), 16);
  EXPECT_EQ(view.FirstNotClearlyAbove(55.f, 46.f, 1.f, 0.f, 0, 30, -200.f), 16);
}

}  // namespace
}  // namespace chromatag::internal
