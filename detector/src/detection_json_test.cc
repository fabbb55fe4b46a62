#include "chromatag/detector/detection_json.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

Detection Sample() {
  Detection d;
  d.family = TagFamily::Load("16h5").get();
  d.id = 3;
  d.hamming = 1;
  d.decision_margin = 7.25;
  d.corners = {cv::Point2d(10, 20), cv::Point2d(30.5, 20), cv::Point2d(30.5, 40),
               cv::Point2d(10, 40)};
  d.green_corners = {cv::Point2d(12, 22), cv::Point2d(28, 22), cv::Point2d(28, 38),
                     cv::Point2d(12, 38)};
  d.red_corners = {cv::Point2d(14, 24), cv::Point2d(26, 24), cv::Point2d(26, 36),
                   cv::Point2d(14, 36)};
  return d;
}

// The text `chromatag detect --json` has always written: keys in
// alphabetical order, numbers as the shortest text that reads back.
TEST(DetectionJsonTest, OneDetectionAsTheCliWritesIt) {
  EXPECT_EQ(DetectionJson(Sample()),
            R"({"corners":[[10.0,20.0],[30.5,20.0],[30.5,40.0],[10.0,40.0]],"family":"16h5",)"
            R"("green_corners":[[12.0,22.0],[28.0,22.0],[28.0,38.0],[12.0,38.0]],"hamming":1,)"
            R"("id":3,"margin":7.25,)"
            R"("red_corners":[[14.0,24.0],[26.0,24.0],[26.0,36.0],[14.0,36.0]]})");
  Detection posed = Sample();
  posed.has_pose = true;
  posed.pose.rvec = {0.1, -0.2, 3.0};
  posed.pose.tvec = {0.01, 0.02, 0.5};
  posed.pose.rms_error_px = 0.25;
  posed.pose.ambiguity = 0.125;
  for (int i = 0; i < 36; ++i) posed.pose.covariance.val[i] = i == 1 ? 0.5 : i == 35 ? 2.0 : 0.0;
  const std::string text = DetectionJson(posed);
  // The covariance as ROS writes one: 36 numbers, row-major.
  EXPECT_NE(text.find(R"("pose":{"ambiguity":0.125,"covariance":[0.0,0.5,0.0,)"), std::string::npos)
      << text;
  EXPECT_NE(text.find(R"(,2.0],"rms_error_px":0.25,"rvec":[0.1,-0.2,3.0],)"
                      R"("tvec":[0.01,0.02,0.5]})"),
            std::string::npos)
      << text;
}

TEST(DetectionJsonTest, FrameLineWithBoardRejectedAndOverlay) {
  FrameJsonRecord frame;
  frame.file = "a\xff.png";  // Not UTF-8: written with U+FFFD.
  frame.frame = 2;
  frame.width = 640;
  frame.height = 480;
  frame.time_us = 1500.5;
  EXPECT_EQ(FrameJson(frame, {}),
            "{\"detections\":[],\"file\":\"a\xef\xbf\xbd.png\",\"frame\":2,\"height\":480,"
            "\"time_us\":1500.5,\"width\":640}");

  Board board;
  board.name = "pair";
  BoardTag tag;
  tag.family = "16h5";
  tag.id = 3;
  tag.size = 0.04;
  board.tags = {tag};
  BoardPose pose;
  pose.rvec = {0, 0, 0};
  pose.tvec = {0, 0, 1};
  pose.tags_used = {0};
  pose.rms_error_px = 0.5;
  RejectedCandidate rejected;
  rejected.seed = {5, 6};
  rejected.centre = {7.5f, 8.5f};
  RejectedCandidate grown = rejected;  // Lost again after GrowRegion.
  grown.grown = true;
  grown.grow_reason = RejectReason::kNoQuietZone;
  std::vector<RejectedCandidate> all_rejected = {rejected, grown};
  frame.board = &board;
  frame.board_pose = &pose;
  frame.rejected = &all_rejected;
  frame.timestamp = 12.5;
  frame.overlay = "out/a.png";
  const std::string line = FrameJson(frame, {Sample()});
  EXPECT_NE(line.find(R"("board":{"ambiguity":0.0,"covariance":[0.0,)"), std::string::npos) << line;
  EXPECT_NE(line.find(R"(,0.0],"name":"pair","rms_error_px":0.5,)"
                      R"("rvec":[0.0,0.0,0.0],"tags_rejected":[],"tags_used":[3],)"
                      R"("tvec":[0.0,0.0,1.0]})"),
            std::string::npos)
      << line;
  EXPECT_NE(line.find(std::string("\"detections\":[") + DetectionJson(Sample()) + "]"),
            std::string::npos)
      << line;
  EXPECT_NE(line.find(R"("overlay":"out/a.png")"), std::string::npos) << line;
  EXPECT_NE(line.find(R"("rejected":[{"centre":[7.5,8.5],"outline":[],"reason":)"),
            std::string::npos)
      << line;
  EXPECT_NE(line.find(R"("timestamp":12.5)"), std::string::npos) << line;
  // Only the candidate GrowRegion tried says why that failed too.
  const size_t grow = line.find(R"("grow_reason":")" +
                                std::string(RejectReasonName(RejectReason::kNoQuietZone)) + "\"");
  EXPECT_NE(grow, std::string::npos) << line;
  EXPECT_EQ(line.find("grow_reason"), grow + 1) << line;  // The first and only one.
  EXPECT_EQ(line.find("grow_reason", grow + 2), std::string::npos) << line;

  frame.board_pose = nullptr;  // The board not seen.
  EXPECT_NE(FrameJson(frame, {}).find(R"("board":null)"), std::string::npos);
}

}  // namespace
}  // namespace chromatag
