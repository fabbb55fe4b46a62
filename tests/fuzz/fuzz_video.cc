// A video file as `chromatag detect` reads one (cli/sources.cc OpenSource
// and the reader of command_detect.cc): opened by path with OpenCV's
// default backend choice, its frame count asked, frames read until one
// fails, frames that are not 8-bit colour refused, and the detector run on
// each. The bytes go to an .avi file of this process's own in /tmp,
// removed after each run. At most kMaxFrames frames are read, and frames
// over kMaxDetectPixels are decoded but not searched, so that a run stays
// fast.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "chromatag/detector/detector.h"

namespace {

constexpr int kMaxFrames = 3;
constexpr size_t kMaxDetectPixels = 640 * 480;

const chromatag::Detector& GetDetector() {
  static const auto detector = [] {
    chromatag::DetectorOptions options;
    options.families = chromatag::TagFamily::Names();
    return chromatag::Detector::Create(options);
  }();
  return *detector;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const chromatag::Detector& detector = GetDetector();
  const std::string path = "/tmp/chromatag-fuzz-video-" + std::to_string(getpid()) + ".avi";
  {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  {
    cv::VideoCapture capture;
    if (capture.open(path)) {
      capture.get(cv::CAP_PROP_FRAME_COUNT);
      chromatag::DetectionResult result;
      for (int i = 0; i < kMaxFrames; ++i) {
        cv::Mat frame;
        if (!capture.read(frame) || frame.empty() || frame.type() != CV_8UC3) break;
        capture.get(cv::CAP_PROP_POS_MSEC);
        if (frame.total() <= kMaxDetectPixels)
          detector.Detect(frame, chromatag::PixelOrder::kBgr, &result);
      }
    }
  }                           // The capture closes the file before it is removed.
  std::remove(path.c_str());  // Nothing left in /tmp when the run ends.
  return 0;
}
