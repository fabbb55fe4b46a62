#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "stages.h"

namespace chromatag::internal {
namespace {

// BGR: grey a* = 0, green a* far below it, red far above.
const cv::Scalar kGrey(128, 128, 128), kGreen(70, 160, 40), kRed(50, 40, 200);

// Columns [x0, x1) and rows [y0, y1) of each drawn rectangle.
struct Box {
  int x0, y0, x1, y1;
  bool HasRow(int y) const { return y0 <= y && y < y1; }
};
constexpr Box kGreenBox{37, 30, 161, 150}, kRedBox{70, 61, 131, 119};
// Wide enough for odd sample counts and the vector paths' tails.
const cv::Size kFrame(203, 180);

cv::Mat RenderScene() {
  cv::Mat image(kFrame, CV_8UC3, kGrey);
  for (const auto& [box, colour] : {std::pair(kGreenBox, kGreen), std::pair(kRedBox, kRed)}) {
    cv::rectangle(image, cv::Rect(box.x0, box.y0, box.x1 - box.x0, box.y1 - box.y0), colour,
                  cv::FILLED);
  }
  return image;
}

// The first sampled column at or after x.
int FirstSampleFrom(int x, int step) { return (x + step - 1) / step * step; }

// Every seed FindADiff returns on row y, in order.
std::vector<cv::Point> Seeds(const ImageView& view, const DetectorOptions& options,
                             const std::vector<DetectedArea>& skip, int y) {
  RowCursor cursor;
  cursor.y = y;
  std::vector<cv::Point> seeds;
  cv::Point seed;
  int rejects = 0;
  while (FindADiff(view, options, skip, &cursor, &seed, &rejects)) seeds.push_back(seed);
  return seeds;
}

class FindADiffTest : public testing::TestWithParam<int> {
 protected:
  DetectorOptions Options() const {
    DetectorOptions options;
    options.step = GetParam();
    return options;
  }
};

// On each sampled row the seeds are the first samples past the rises in a*:
// green to red where the row crosses the red, green to grey on the green's
// right. Grey to green and red to green fall and give none.
TEST_P(FindADiffTest, SeedsAtTheRisesInA) {
  const cv::Mat image = RenderScene();
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const DetectorOptions options = Options();
  for (int y = 0; y < image.rows; y += options.step) {
    std::vector<cv::Point> expected;
    if (kRedBox.HasRow(y)) expected.emplace_back(FirstSampleFrom(kRedBox.x0, options.step), y);
    if (kGreenBox.HasRow(y)) expected.emplace_back(FirstSampleFrom(kGreenBox.x1, options.step), y);
    EXPECT_EQ(Seeds(view, options, {}, y), expected) << "row " << y;
  }
}

// A flat frame has no seeds on any row.
TEST_P(FindADiffTest, FlatFrameHasNoSeeds) {
  const cv::Mat image(kFrame, CV_8UC3, kGrey);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const DetectorOptions options = Options();
  for (int y = 0; y < image.rows; y += options.step) {
    EXPECT_TRUE(Seeds(view, options, {}, y).empty()) << "row " << y;
  }
}

// An accepted area over the red suppresses its seeds and no others.
TEST_P(FindADiffTest, SkipsDetectedAreas) {
  const cv::Mat image = RenderScene();
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const DetectorOptions options = Options();
  DetectedArea area;
  const double x0 = kRedBox.x0 - 4, x1 = kRedBox.x1 + 4;
  area.min_y = kRedBox.y0 - 4;
  area.max_y = kRedBox.y1 + 4;
  area.quad = {{{x0, area.min_y}, {x1, area.min_y}, {x1, area.max_y}, {x0, area.max_y}}};
  for (int y = 0; y < image.rows; y += options.step) {
    std::vector<cv::Point> expected;
    if (kGreenBox.HasRow(y)) expected.emplace_back(FirstSampleFrom(kGreenBox.x1, options.step), y);
    EXPECT_EQ(Seeds(view, options, {area}, y), expected) << "row " << y;
  }
}

INSTANTIATE_TEST_SUITE_P(Steps, FindADiffTest, testing::Values(1, 3, 4, 5, 8));

// A quad's span on a row runs between the two sides the row crosses.
TEST(DetectedAreaTest, RowSpanOfADiamond) {
  DetectedArea diamond;
  diamond.quad = {{{50, 10}, {80, 40}, {50, 70}, {20, 40}}};
  diamond.min_y = 10;
  diamond.max_y = 70;
  double begin = 0, end = 0;
  ASSERT_TRUE(diamond.RowSpan(25, &begin, &end));
  EXPECT_DOUBLE_EQ(begin, 35);
  EXPECT_DOUBLE_EQ(end, 65);
  ASSERT_TRUE(diamond.RowSpan(40, &begin, &end));
  EXPECT_DOUBLE_EQ(begin, 20);
  EXPECT_DOUBLE_EQ(end, 80);
  EXPECT_FALSE(diamond.RowSpan(5, &begin, &end));
  EXPECT_FALSE(diamond.RowSpan(71, &begin, &end));
}

}  // namespace
}  // namespace chromatag::internal
