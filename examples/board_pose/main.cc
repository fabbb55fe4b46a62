// A board's pose in a photo: the board file is a sheet's sidecar (from
// `chromatag generate --board 6x4 -o board.pdf`, read board.pdf.json) or a
// bundle YAML in apriltag_ros's tag_bundles shape.
//
//   board_pose photo.jpg board.pdf.json [--camera FILE | --focal PX] [--out drawn.png]
//
// Exits 0 when the board was seen, 1 when it was not or a file could not be
// read, 2 on bad arguments.
//
// --camera reads the camera's calibration (OpenCV, ROS camera_info or Kalibr
// files, as `chromatag calibrate-camera` writes them). Without it the
// intrinsics are a guess: a focal length of --focal pixels, the image width
// by default, and the principal point at the centre.
//
// Everything it uses (detector, board and camera files) links neither
// Ceres, Cairo nor OpenColorIO: ChromaTag::rig and ChromaTag::detector.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/draw.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/rig/board_file.h"
#include "chromatag/rig/camera_file.h"

int main(int argc, char** argv) {
  std::string image_path, board_path, camera_path, out;
  double focal = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--camera" && i + 1 < argc) {
      camera_path = argv[++i];
    } else if (arg == "--focal" && i + 1 < argc) {
      focal = std::atof(argv[++i]);
    } else if (arg == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (!arg.empty() && arg[0] != '-' && image_path.empty()) {
      image_path = arg;
    } else if (!arg.empty() && arg[0] != '-' && board_path.empty()) {
      board_path = arg;
    } else {
      board_path.clear();
      break;
    }
  }
  if (board_path.empty()) {
    std::fprintf(stderr, "usage: %s IMAGE BOARD_FILE [--camera FILE | --focal PX] [--out PNG]\n",
                 argv[0]);
    return 2;
  }

  std::string error;
  const auto board = chromatag::ReadBoardFile(board_path, &error);
  if (!board) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  cv::Mat frame = chromatag::ReadImage(image_path, &error);
  if (frame.empty()) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }

  chromatag::CameraIntrinsics camera;
  camera.fx = camera.fy = focal > 0 ? focal : frame.cols;
  camera.cx = (frame.cols - 1) / 2.0;
  camera.cy = (frame.rows - 1) / 2.0;
  if (!camera_path.empty() && !chromatag::LoadCameraFile(camera_path, &camera, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  chromatag::DetectorOptions options;
  options.families.clear();
  for (const chromatag::BoardTag& tag : board->tags) {
    if (options.families.empty() || options.families.back() != tag.family)
      options.families.push_back(tag.family);
  }
  const auto detector = chromatag::Detector::Create(options, &error);
  if (!detector) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }

  const chromatag::DetectionResult result = detector->Detect(frame);
  chromatag::BoardPose pose;
  if (!chromatag::EstimateBoardPose(result.detections, *board, camera, &pose, &error)) {
    std::printf("board %s not seen: %s\n", board->name.c_str(), error.c_str());
    return 1;
  }
  std::printf(
      "board %s: %zu of %zu tags, t = (%.4f, %.4f, %.4f) m, rvec = (%.4f, %.4f, %.4f), "
      "rms %.2f px\n",
      board->name.c_str(), pose.tags_used.size(), board->tags.size(), pose.tvec[0], pose.tvec[1],
      pose.tvec[2], pose.rvec[0], pose.rvec[1], pose.rvec[2], pose.rms_error_px);
  for (int i : pose.detections_rejected) {
    const chromatag::Detection& d = result.detections[i];
    std::printf("  left out: %s %d at (%.1f, %.1f)\n", d.family->name().c_str(), d.id,
                d.corners[0].x, d.corners[0].y);
  }
  if (!out.empty()) {
    chromatag::DrawDetections(result.detections, nullptr, 0, &frame);
    chromatag::DrawBoardPose(pose, board->name, camera, 2 * board->tags[0].size, &frame);
    if (!cv::imwrite(out, frame)) {
      std::fprintf(stderr, "cannot write %s\n", out.c_str());
      return 1;
    }
  }
  return 0;
}
