// calibrate-camera's view selection and camera fit on hostile detections:
// views of a 3 x 2 board whose tags' twelve ring corners (and IDs) come
// from the input, offered one at a time (a live camera), chosen offline (a
// video) and then calibrated with. Corners may be anywhere, repeated,
// collinear, NaN or infinite; nothing may crash, hang or read out of bounds.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "chromatag/calib/camera_calibration.h"
#include "chromatag/calib/view_selection.h"
#include "chromatag/detector/board.h"
#include "chromatag/families/family.h"

namespace {

// Reads the input a value at a time; zeros once it runs out.
struct Reader {
  const uint8_t* data;
  size_t size;
  size_t at = 0;
  uint8_t Byte() { return at < size ? data[at++] : 0; }
  // A coordinate: mostly inside a 640 x 480 image, sometimes far out or
  // not a number.
  double Coordinate() {
    const uint16_t raw = static_cast<uint16_t>(Byte() << 8 | Byte());
    switch (raw >> 13) {
      case 7:
        return std::numeric_limits<double>::quiet_NaN();
      case 6:
        return (raw & 1) ? std::numeric_limits<double>::infinity() : -1e12;
      default:
        return (raw & 0x1fff) * (700.0 / 0x1fff) - 30.0;
    }
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const auto family = chromatag::TagFamily::Load("16h5");
  static const chromatag::Board board = [] {
    chromatag::Board b;
    b.name = "fuzz";
    for (int i = 0; i < 6; ++i) {
      chromatag::BoardTag tag;
      tag.family = "16h5";
      tag.id = family->kept_ids()[i];
      tag.size = 0.03;
      tag.translation = {0.04 * (i % 3), 0.04 * (i / 3), 0.0};
      b.tags.push_back(tag);
    }
    return b;
  }();
  Reader in{data, size};
  const cv::Size image_size(640, 480);
  std::vector<chromatag::CalibrationView> views;
  const int num_views = 1 + in.Byte() % 6;
  for (int v = 0; v < num_views; ++v) {
    chromatag::CalibrationView view;
    view.name = "view " + std::to_string(v);
    const int tags = in.Byte() % 7;
    for (int t = 0; t < tags; ++t) {
      chromatag::Detection d;
      d.family = family.get();
      d.id = family->kept_ids()[in.Byte() % 8];
      for (auto* ring : {&d.corners, &d.green_corners, &d.red_corners})
        for (cv::Point2d& p : *ring) p = {in.Coordinate(), in.Coordinate()};
      view.detections.push_back(d);
    }
    views.push_back(view);
  }
  chromatag::ViewSelectionOptions selection;
  selection.max_views = 4;
  chromatag::ViewSelector live(board, image_size, selection);
  for (const auto& view : views) live.Offer(view.detections);
  chromatag::ViewSelector offline(board, image_size, selection);
  std::vector<chromatag::ViewPose> poses;
  for (const auto& view : views) {
    chromatag::ViewPose pose;
    std::string why;
    if (offline.Describe(view.detections, &pose, &why)) poses.push_back(pose);
  }
  std::vector<std::string> why;
  offline.Choose(poses, &why);
  std::string error;
  chromatag::CalibrateCamera(board, views, image_size, {}, &error);
  return 0;
}
