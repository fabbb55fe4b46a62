// The calibration photo pipeline on arbitrary images: the bytes are read as
// `calibrate` reads a photo (DecodeImage: the size from the header first),
// anything over 256 x 256 pixels is dropped before it is decoded so that a
// run stays in milliseconds, and the calibration sheet of fuzz_sheets.h
// (a real layout, small enough to be seen whole at that size; the seeds
// are photos of it) is looked for with LocateSheet and, when found,
// measured with MeasurePhoto.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <opencv2/core.hpp>

#include "chromatag/base/input_file.h"
#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/locate_sheet.h"
#include "chromatag/calib/measure.h"
#include "chromatag/detector/read_image.h"
#include "fuzz_sheets.h"

namespace {

constexpr uint64_t kMaxSide = 256;

void Check(bool ok, const char* promise) {
  if (ok) return;
  std::fprintf(stderr, "broken promise: %s\n", promise);
  std::abort();
}

const chromatag::CalibSheetLayout& Layout() {
  static const chromatag::CalibSheetLayout* layout = [] {
    std::string error;
    auto made = chromatag::LayoutCalibSheet(chromatag::fuzz::CalibSheet(), &error);
    if (!made) {
      std::fprintf(stderr, "fuzz_locate_sheet: no layout: %s\n", error.c_str());
      std::abort();
    }
    return new chromatag::CalibSheetLayout(std::move(*made));
  }();
  return *layout;
}

void CheckLocation(const chromatag::SheetLocation& location, const chromatag::LocateOptions& o) {
  for (int i = 0; i < 9; ++i)
    Check(std::isfinite(location.image_from_page.val[i]), "a finite homography");
  Check(location.rms_mm >= 0 && location.rms_mm <= o.max_rms_mm, "a fit within max_rms_mm");
  Check(std::isfinite(location.px_per_mm) && location.px_per_mm > 0, "a positive scale");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const chromatag::CalibSheetLayout& layout = Layout();
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  chromatag::ImageSize claimed;
  if (!chromatag::ImageBytesSize(bytes, &claimed) || claimed.width > kMaxSide ||
      claimed.height > kMaxSide)
    return 0;
  std::string error;
  const cv::Mat bgr = chromatag::DecodeImage(bytes, "photo", &error);
  if (bgr.empty()) {
    Check(!error.empty(), "a refusal says why");
    return 0;
  }
  Check(bgr.type() == CV_8UC3, "8-bit BGR");
  // The budget gate holds only if the decoder makes no more pixels than
  // the header it was judged by claims.
  Check(static_cast<uint64_t>(bgr.total()) <= claimed.width * claimed.height,
        "no more pixels than the header claims");

  const chromatag::LocateOptions locate;
  const auto location = chromatag::LocateSheet(bgr, layout, locate, &error);
  if (!location) {
    Check(!error.empty(), "LocateSheet: a refusal says why");
    return 0;
  }
  CheckLocation(*location, locate);
  error.clear();
  const auto measured = chromatag::MeasurePhoto(bgr, layout, {}, locate, &error);
  if (!measured) {
    Check(!error.empty(), "MeasurePhoto: a refusal says why");
    return 0;
  }
  CheckLocation(measured->location, locate);
  Check(measured->patches.size() == layout.patches.size(), "every patch measured");
  for (size_t i = 0; i < measured->patches.size(); ++i)
    Check(measured->patches[i].index == static_cast<int>(i), "patches in layout order");
  return 0;
}
