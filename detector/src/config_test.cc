#include "chromatag/detector/config.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

TEST(DetectorConfigTest, RoundTripsEveryField) {
  DetectorOptions options;
  options.families = {"36h11"};
  options.step = 3;
  options.row_step = 5;
  options.adiff_thresh = 12.5;
  options.border_thresh = 7.25;
  options.border_run = 4;
  options.max_green_a = -4.5;
  options.conv_thresh = 0.9;
  options.max_hamming = 1;
  options.min_decision_margin = 1.5;
  options.two_step_rises = true;
  options.white_balance = {0.625, 1.0, 0.8125};
  DetectorOptions back;
  std::string error;
  ASSERT_TRUE(ParseDetectorConfig(DetectorConfigToJson(options), &back, &error)) << error;
  EXPECT_EQ(back.families, options.families);
  EXPECT_EQ(back.step, 3);
  EXPECT_EQ(back.row_step, 5);
  EXPECT_TRUE(back.two_step_rises);
  EXPECT_DOUBLE_EQ(back.adiff_thresh, 12.5);
  EXPECT_DOUBLE_EQ(back.border_thresh, 7.25);
  EXPECT_EQ(back.border_run, 4);
  EXPECT_DOUBLE_EQ(back.max_green_a, -4.5);
  EXPECT_DOUBLE_EQ(back.conv_thresh, 0.9);
  EXPECT_EQ(back.max_hamming, 1);
  EXPECT_DOUBLE_EQ(back.min_decision_margin, 1.5);
  EXPECT_EQ(back.white_balance, options.white_balance);
}

// A config without a white balance leaves the caller's (none by default);
// one with it sets all three gains, written as a list.
TEST(DetectorConfigTest, WhiteBalanceIsAListOfThreeGains) {
  const auto config = [](const std::string& options) {
    return R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": )" + options +
           "}";
  };
  DetectorOptions options;
  std::string error;
  ASSERT_TRUE(ParseDetectorConfig(config(R"({"adiff_thresh": 20})"), &options, &error)) << error;
  EXPECT_EQ(options.white_balance, (std::array<double, 3>{1.0, 1.0, 1.0}));
  ASSERT_TRUE(ParseDetectorConfig(config(R"({"white_balance": [1, 0.6, 0.9]})"), &options, &error))
      << error;
  EXPECT_EQ(options.white_balance, (std::array<double, 3>{1.0, 0.6, 0.9}));
  EXPECT_NE(DetectorConfigToJson(options, {"white_balance"}).find("\"white_balance\": [\n"),
            std::string::npos);
  const struct {
    const char* options;
    const char* says;
  } bad[] = {
      {R"({"white_balance": 0.8})", "\"white_balance\" must be a list of three numbers, [r, g, b]"},
      {R"({"white_balance": [1, 0.8]})", "must be a list of three numbers"},
      {R"({"white_balance": [1, "0.8", 1]})", "\"white_balance\" must be a number"},
      {R"({"white_balance": [1.5, 1, 1.5]})",
       "the largest gain must be 1; divide all three by it: [1, 0.667, 1]"},
      {R"({"white_balance": [1, 0.1, 1]})", "a gain below 0.2"},
      {R"({"white_balance": [1, 0, 1]})", "gains must be finite and positive"},
  };
  for (const auto& c : bad) {
    DetectorOptions kept;
    kept.white_balance = {1.0, 0.5, 0.5};
    EXPECT_FALSE(ParseDetectorConfig(config(c.options), &kept, &error)) << c.options;
    EXPECT_NE(error.find(c.says), std::string::npos) << error;
    EXPECT_EQ(kept.white_balance, (std::array<double, 3>{1.0, 0.5, 0.5}));
  }
}

// One table of names: the file written holds each name once, an unknown
// name is refused with all of them listed, and benchmark switches are not
// options (refine_corners, once one, is read as true only).
TEST(DetectorConfigTest, OneTableNamesEveryField) {
  const auto config = [](const std::string& options) {
    return R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": )" + options +
           "}";
  };
  const std::string text = DetectorConfigToJson(DetectorOptions{});
  DetectorOptions options;
  std::string error;
  EXPECT_FALSE(ParseDetectorConfig(config(R"({"grow_regions": false})"), &options, &error));
  EXPECT_NE(error.find("unknown option \"grow_regions\""), std::string::npos) << error;
  for (const std::string& name : DetectorConfigFieldNames()) {
    EXPECT_NE(text.find("\"" + name + "\""), std::string::npos) << name;
    EXPECT_NE(error.find(name), std::string::npos) << error;
  }
  EXPECT_EQ(DetectorConfigFieldNames().size(), 13u);
  EXPECT_EQ(text.find("refine_corners"), std::string::npos);
  EXPECT_TRUE(
      ParseDetectorConfig(config(R"({"refine_corners": true, "step": 2})"), &options, &error))
      << error;
  EXPECT_EQ(options.step, 2);
  EXPECT_FALSE(ParseDetectorConfig(config(R"({"refine_corners": false})"), &options, &error));
  EXPECT_NE(error.find("always on"), std::string::npos) << error;
}

TEST(DetectorConfigTest, SubsetKeepsTheCallersOtherValues) {
  DetectorOptions derived;
  derived.adiff_thresh = 9;
  const std::string text =
      DetectorConfigToJson(derived, {"adiff_thresh"}, R"({"sheet_id": 7, "note": "x"})");
  EXPECT_EQ(text.find("border_thresh"), std::string::npos);
  EXPECT_NE(text.find("\"sheet_id\": 7"), std::string::npos);
  DetectorOptions options;
  options.families = {"36h11"};
  options.border_thresh = 6;
  std::string error;
  ASSERT_TRUE(ParseDetectorConfig(text, &options, &error)) << error;
  EXPECT_DOUBLE_EQ(options.adiff_thresh, 9);
  EXPECT_DOUBLE_EQ(options.border_thresh, 6);
  EXPECT_EQ(options.families, std::vector<std::string>{"36h11"});
}

TEST(DetectorConfigTest, RefusesBadFilesAndLeavesOptionsAlone) {
  const struct {
    const char* text;
    const char* says;
  } cases[] = {
      {"{", "not valid JSON"},
      {R"({"schema": "chromatag-layout", "schema_version": 1, "options": {}})", "not a detector"},
      // Another tool's file is named by its kind, not by its first odd member.
      {R"({"schema": "chromatag-calib-sheet", "schema_version": 1, "tool": {}})",
       "this is a \"chromatag-calib-sheet\" file, not a detector config"},
      {R"({"format": "chromatag-palette", "version": 1})",
       "this is a \"chromatag-palette\" file, not a detector config"},
      {R"({"schema": "chromatag-detector-config", "schema_version": 2, "options": {}})",
       "schema_version"},
      {R"({"schema": "chromatag-detector-config", "schema_version": 1})", "missing \"options\""},
      {R"({"schema": "chromatag-detector-config", "options": {}})", "missing \"schema_version\""},
      {R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": {"adif_thresh": 3}})",
       "unknown option \"adif_thresh\""},
      // 4294967300 wrapped to a step of 4; max_hamming 50 passed here
      // and was refused only by Detector::Create.
      {R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": {"step": 4294967300}})",
       "\"step\" is out of range"},
      {R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": {"max_hamming": 50}})",
       "max_hamming 50 is unsafe for 16h5: at most 2"},
      {R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": {"step": 2.5}})",
       "\"step\" must be an integer"},
      {R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": {"adiff_thresh": -1}})",
       "adiff_thresh (ADiffThresh) must be in (0, 200]"},
      {R"({"schema": "chromatag-detector-config", "schema_version": 1, "options": {}, "x": 1})",
       "unknown member \"x\""},
  };
  for (const auto& c : cases) {
    DetectorOptions options;
    options.adiff_thresh = 11;
    std::string error;
    EXPECT_FALSE(ParseDetectorConfig(c.text, &options, &error)) << c.text;
    EXPECT_NE(error.find(c.says), std::string::npos) << error;
    EXPECT_DOUBLE_EQ(options.adiff_thresh, 11);
  }
  DetectorOptions options;
  std::string error;
  EXPECT_FALSE(LoadDetectorConfig("/nonexistent/detector.json", &options, &error));
  EXPECT_NE(error.find("/nonexistent/detector.json"), std::string::npos);
}

}  // namespace
}  // namespace chromatag
