#include "chromatag/detector/detector.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace chromatag {
namespace {

TEST(DetectorTest, RefusesInvalidOptionsNamingTheField) {
  DetectorOptions options;
  options.step = 0;
  std::string error;
  EXPECT_EQ(Detector::Create(options, &error), nullptr);
  EXPECT_NE(error.find("step (N)"), std::string::npos) << error;
  options = {};
  options.camera = CameraIntrinsics{};
  EXPECT_EQ(Detector::Create(options, &error), nullptr);
  EXPECT_NE(error.find("fx and fy"), std::string::npos) << error;
  options.camera->fx = options.camera->fy = 500;
  options.camera->distortion = {0.1, 0.2, 0.3};
  EXPECT_EQ(Detector::Create(options, &error), nullptr);
  EXPECT_NE(error.find("0, 4, 5 or 8"), std::string::npos) << error;
}

// AprilTag's names are accepted; options() reports the library's, once each.
TEST(DetectorTest, FamiliesAreNamedOnceTheLibrarysWay) {
  DetectorOptions options;
  options.families = {"tag36h11", "16h5", "36h11"};
  const auto detector = Detector::Create(options);
  ASSERT_TRUE(detector);
  EXPECT_EQ(detector->options().families, (std::vector<std::string>{"36h11", "16h5"}));
}

TEST(DetectorTest, AnythingButEightBitThreeChannelGivesAnEmptyResult) {
  auto detector = Detector::Create(DetectorOptions{});
  ASSERT_TRUE(detector);
  for (int type : {CV_8UC1, CV_8UC4, CV_16UC3, CV_32FC3}) {
    const cv::Mat image(64, 64, type, cv::Scalar::all(1));
    EXPECT_TRUE(detector->Detect(image).detections.empty());
  }
  EXPECT_TRUE(detector->Detect(cv::Mat()).detections.empty());
}

TEST(DetectorTest, FlatAndTinyFramesHaveNoCandidates) {
  auto detector = Detector::Create(DetectorOptions{});
  for (cv::Size size : {cv::Size(1, 1), cv::Size(3, 500), cv::Size(752, 480)}) {
    const DetectionResult result =
        detector->Detect(cv::Mat(size, CV_8UC3, cv::Scalar(40, 200, 90)));
    EXPECT_TRUE(result.detections.empty());
    EXPECT_EQ(result.summary.seeds, 0);
  }
}

// A red square on green seeds FindADiff and passes InitialScan's red/green
// test but has no black and white rings: rejected, and counted.
TEST(DetectorTest, RedOnGreenWithoutRingsIsRejectedAndCounted) {
  auto detector = Detector::Create(DetectorOptions{});
  cv::Mat image(200, 200, CV_8UC3, cv::Scalar(60, 160, 40));  // BGR green.
  cv::rectangle(image, cv::Rect(80, 80, 40, 40), cv::Scalar(60, 20, 220), cv::FILLED);
  const DetectionResult result = detector->Detect(image);
  EXPECT_TRUE(result.detections.empty());
  EXPECT_GT(result.summary.seeds, 0);
  EXPECT_EQ(result.summary.rejected[static_cast<int>(Stage::kInitialScan)], result.summary.seeds);
}

// The stages are timed only when asked (each timing reads the clock twice a
// candidate); the frame's total always is.
TEST(DetectorTest, StagesAreTimedOnlyWithTimeStages) {
  cv::Mat image(200, 200, CV_8UC3, cv::Scalar(60, 160, 40));  // BGR green.
  cv::rectangle(image, cv::Rect(80, 80, 40, 40), cv::Scalar(60, 20, 220), cv::FILLED);
  for (bool time_stages : {false, true}) {
    DetectorOptions options;
    options.time_stages = time_stages;
    auto detector = Detector::Create(options);
    ASSERT_TRUE(detector);
    const DetectorSummary summary = detector->Detect(image).summary;
    ASSERT_GT(summary.seeds, 0);
    EXPECT_GT(summary.total_time_us, 0.0);
    const double find_adiff = summary.stage_time_us[static_cast<int>(Stage::kFindADiff)];
    const double initial_scan = summary.stage_time_us[static_cast<int>(Stage::kInitialScan)];
    if (time_stages) {
      EXPECT_GT(initial_scan, 0.0);
      EXPECT_GT(find_adiff, 0.0);
      EXPECT_LE(find_adiff + initial_scan, summary.total_time_us + 1e-6);
    } else {
      for (double us : summary.stage_time_us) EXPECT_EQ(us, 0.0);
    }
  }
}

// FindADiff samples every sampled_row_step()-th row from the top: a red square
// on green seeds once on each sampled row that crosses it, at its left edge.
TEST(DetectorTest, RowStepSetsTheRowsThatSeed) {
  cv::Mat image(200, 200, CV_8UC3, cv::Scalar(60, 160, 40));  // BGR green.
  const cv::Rect red(80, 81, 40, 40);                         // Rows 81-120.
  cv::rectangle(image, red, cv::Scalar(60, 20, 220), cv::FILLED);
  for (int row_step : {0, 5, 7}) {
    DetectorOptions options;
    options.row_step = row_step;
    options.report_rejected = true;
    auto detector = Detector::Create(options);
    ASSERT_TRUE(detector);
    const int rows = options.sampled_row_step();
    int expected = 0;
    for (int y = 0; y < image.rows; y += rows) expected += red.y <= y && y < red.br().y;
    const DetectionResult result = detector->Detect(image);
    EXPECT_EQ(result.summary.seeds, expected) << "row_step " << row_step;
    ASSERT_EQ(static_cast<int>(result.rejected.size()), expected);
    for (const RejectedCandidate& candidate : result.rejected) {
      EXPECT_EQ(candidate.seed.y % rows, 0) << "row_step " << row_step;
      EXPECT_EQ(candidate.seed.x, red.x) << "row_step " << row_step;
    }
  }
}

}  // namespace
}  // namespace chromatag
