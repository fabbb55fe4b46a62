#include "chromatag/detector/options.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace chromatag
