// The detector on arbitrary images: the first bytes choose the size, the
// stride padding, a region of interest, the pixel order and the options
// (step, families, sub-pixel corners, pose), the rest are the pixels.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

#include <opencv2/core.hpp>

#include "chromatag/detector/detector.h"
#include "stage_switches.h"

namespace {

const chromatag::Detector* DetectorFor(uint8_t choice) {
  static std::unique_ptr<chromatag::Detector> detectors[8];
  auto& slot = detectors[choice % 8];
  if (!slot) {
    chromatag::DetectorOptions options;
    options.families = (choice & 1) ? std::vector<std::string>{"16h5", "36h11"}
                                    : std::vector<std::string>{"36h11"};
    options.step = (choice & 2) ? 1 : 4;
    options.row_step = (choice & 3) == 1 ? 5 : 0;  // Rows apart from columns.
    options.two_step_rises = (choice & 3) == 3;    // With step 1 and every row.
    options.report_rejected = true;
    if (choice & 4) {
      options.camera = chromatag::CameraIntrinsics{300, 300, 40, 30, {0.1, -0.05, 0, 0}};
      options.tag_size = 0.05;
    }
    chromatag::internal::StageSwitches switches;
    switches.refine_corners = (choice & 4) == 0;
    slot = chromatag::internal::CreateDetector(options, switches);
  }
  return slot.get();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 6) return 0;
  const int width = 1 + data[0] % 96;
  const int height = 1 + data[1] % 96;
  const int pad = data[2] % 8;  // Extra bytes per row: a stride that is not 3 * width.
  const auto order = (data[3] & 1) ? chromatag::PixelOrder::kRgb : chromatag::PixelOrder::kBgr;
  const chromatag::Detector* detector = DetectorFor(data[4]);
  const bool roi = data[5] & 1;
  data += 6;
  size -= 6;
  const size_t step = static_cast<size_t>(width) * 3 + pad;
  std::vector<uint8_t> pixels(step * height + 16, 0);
  std::memcpy(pixels.data(), data, std::min(size, pixels.size()));
  cv::Mat image(height, width, CV_8UC3, pixels.data(), step);
  if (roi && width > 4 && height > 4) image = image(cv::Rect(1, 2, width - 3, height - 4));
  chromatag::DetectionResult result;
  detector->Detect(image, order, &result);
  return 0;
}
