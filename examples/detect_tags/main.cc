// Detect ChromaTags in an image or a camera's frames, print each tag's ID,
// corners and pose, and draw them.
//
//   detect_tags photo.jpg [--tag-size 0.04] [--out drawn.png]
//   detect_tags --camera-index 0 [--tag-size 0.04] (a live window; q quits)
//
// Exits 0 when the (last) frame held a tag, 1 when it held none or could not
// be read, 2 on bad arguments.
//
// Without calibrated intrinsics the pose uses a guess: a focal length of the
// image width and the principal point at the centre. Use your camera's own.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "chromatag/detector/detector.h"
#include "chromatag/detector/draw.h"
#include "chromatag/detector/read_image.h"

namespace {

void Print(const chromatag::DetectionResult& result) {
  for (const chromatag::Detection& d : result.detections) {
    std::printf("tag %s %d (bits corrected %d, margin %.1f) corners", d.family->name().c_str(),
                d.id, d.hamming, d.decision_margin);
    for (const cv::Point2d& c : d.corners) std::printf(" (%.2f, %.2f)", c.x, c.y);
    if (d.has_pose) {
      std::printf(" at (%.3f, %.3f, %.3f) m", d.pose.tvec[0], d.pose.tvec[1], d.pose.tvec[2]);
    }
    std::printf("\n");
  }
  std::printf("%zu tag(s) in %.0f us\n", result.detections.size(), result.summary.total_time_us);
}

}  // namespace

int main(int argc, char** argv) {
  std::string input, out;
  int camera = -1;
  double tag_size = 0.04;  // Side of the black square, metres.
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--camera-index" && i + 1 < argc) {
      camera = std::atoi(argv[++i]);
    } else if (arg == "--tag-size" && i + 1 < argc) {
      tag_size = std::atof(argv[++i]);
    } else if (arg == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (!arg.empty() && arg[0] != '-') {
      input = arg;
    } else {
      std::fprintf(stderr, "usage: %s IMAGE [--tag-size M] [--out PNG] | --camera-index N\n",
                   argv[0]);
      return 2;
    }
  }
  if (input.empty() && camera < 0) {
    std::fprintf(stderr, "usage: %s IMAGE [--tag-size M] [--out PNG] | --camera-index N\n",
                 argv[0]);
    return 2;
  }

  cv::VideoCapture capture;
  cv::Mat frame;
  if (camera >= 0) {
    if (!capture.open(camera) || !capture.read(frame)) {
      std::fprintf(stderr, "cannot read camera %d\n", camera);
      return 1;
    }
  } else {
    std::string error;
    frame = chromatag::ReadImage(input, &error);
    if (frame.empty()) {
      std::fprintf(stderr, "%s\n", error.c_str());
      return 1;
    }
  }

  chromatag::DetectorOptions options;
  options.families = {"16h5", "36h11"};
  chromatag::CameraIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = frame.cols;
  intrinsics.cx = frame.cols / 2.0;
  intrinsics.cy = frame.rows / 2.0;
  options.camera = intrinsics;
  options.tag_size = tag_size;
  std::string error;
  const auto detector = chromatag::Detector::Create(options, &error);
  if (!detector) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }

  chromatag::DetectionResult result;
  do {
    detector->Detect(frame, chromatag::PixelOrder::kBgr, &result);
    Print(result);
    chromatag::DrawDetections(result.detections, &intrinsics, tag_size, &frame);
    if (camera < 0) break;
    cv::imshow("ChromaTag", frame);
    if (cv::waitKey(1) == 'q') break;
  } while (capture.read(frame));

  if (!out.empty() && !cv::imwrite(out, frame)) {
    std::fprintf(stderr, "cannot write %s\n", out.c_str());
    return 1;
  }
  return result.detections.empty() ? 1 : 0;
}
