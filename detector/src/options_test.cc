#include "chromatag/detector/options.h"

#include <gtest/gtest.h>

#include <cmath>

namespace chromatag {
namespace {

TEST(DetectorOptionsTest, DefaultsAreThePapersAndValid) {
  DetectorOptions options;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  EXPECT_EQ(options.step, 4);
  EXPECT_EQ(options.row_step, 0);
  EXPECT_EQ(options.sampled_row_step(), 4);
  EXPECT_EQ(options.adiff_thresh, 25.0);
  EXPECT_EQ(options.border_thresh, 5.0);
  EXPECT_EQ(options.border_run, 3);
  EXPECT_EQ(options.conv_thresh, 0.98);
}

TEST(DetectorOptionsTest, RowStepDefaultsToStep) {
  DetectorOptions options;
  options.step = 6;
  EXPECT_EQ(options.sampled_row_step(), 6);
  options.row_step = 5;
  std::string error;
  EXPECT_TRUE(options.IsValid(&error)) << error;
  EXPECT_EQ(options.sampled_row_step(), 5);
}

TEST(DetectorOptionsTest, RefusesOutOfRangeValuesNamingTheField) {
  std::string error;
  DetectorOptions options;
  options.step = 0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("step (N)"), std::string::npos) << error;
  options = {};
  for (int row_step : {-1, 65}) {
    options.row_step = row_step;
    EXPECT_FALSE(options.IsValid(&error));
    EXPECT_NE(error.find("row_step"), std::string::npos) << error;
  }
  options = {};
  options.families = {"25h9"};
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("unknown family '25h9'"), std::string::npos) << error;
  options = {};
  options.conv_thresh = 1.0;
  EXPECT_FALSE(options.IsValid(&error));
  options = {};
  options.adiff_thresh = -1.0;
  EXPECT_FALSE(options.IsValid(&error));
  options = {};
  options.max_green_a = 150.0;
  EXPECT_FALSE(options.IsValid(&error));
  EXPECT_NE(error.find("max_green_a"), std::string::npos) << error;
}

// Gains on linear light only darken channels: the largest is 1, none below
// kMinWhiteBalanceGain; the message says what is allowed.
TEST(DetectorOptionsTest, WhiteBalanceGainsAreCheckedAndExplained) {
  DetectorOptions options;
  std::string error;
  for (const std::array<double, 3>& good :
       {std::array<double, 3>{1, 1, 1}, {1, 0.6, 1}, {0.2, 1, 0.2}, {0.45, 0.7, 1}}) {
    options.white_balance = good;
    EXPECT_TRUE(options.IsValid(&error)) << error;
  }
  const double nan = std::nan("");
  const struct {
    std::array<double, 3> gains;
    const char* says;
  } bad[] = {
      {{1.5, 1.0, 1.5}, "the largest gain must be 1"},
      {{0.5, 0.8, 0.5}, "divide all three by it: [0.625, 1, 0.625]"},
      {{1.0, 0.19, 1.0}, "a gain below 0.2"},
      {{1.0, -1.0, 1.0}, "finite and positive"},
      {{1.0, nan, 1.0}, "finite and positive"},
  };
  for (const auto& c : bad) {
    options.white_balance = c.gains;
    EXPECT_FALSE(options.IsValid(&error));
    EXPECT_NE(error.find(c.says), std::string::npos) << error;
    EXPECT_NE(error.find("(gains for R, G, B on linear light, each in [0.2, 1], the largest 1"),
              std::string::npos)
        << error;
  }
}

}  // namespace
}  // namespace chromatag
