// Writes the photos behind docs/calibration.md's "Through a real press
// profile (ICC)" (not a test): a calibration sheet or a tag sheet printed
// through Ghostscript's SWOP press (icc_press.h) and photographed under the
// tungsten and daylight of icc_press_test. Usage:
//   make_icc_press_photos SIDECAR PREFIX
// with the sidecar of 'chromatag calib-sheet' or of 'chromatag generate' (its
// first page), writes PREFIX-tungsten.png and PREFIX-daylight.png; and
//   make_icc_press_photos --shrink IN.png OUT.png WIDTH
// scales a picture down for the docs.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calib_sim.h"
#include "chromatag/layout/calib_sheet_layout.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/raster.h"
#include "icc_press.h"

namespace {

int Shrink(const std::string& in, const std::string& out, int width) {
  const cv::Mat image = cv::imread(in, cv::IMREAD_COLOR);
  if (image.empty() || width <= 0 || width > image.cols) {
    std::cerr << "make_icc_press_photos: cannot shrink " << in << " to " << width << " px\n";
    return 2;
  }
  cv::Mat small;
  const int height = static_cast<int>(std::lround(image.rows * double(width) / image.cols));
  cv::resize(image, small, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  return cv::imwrite(out, small) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace chromatag;
  if (argc == 5 && std::string(argv[1]) == "--shrink")
    return Shrink(argv[2], argv[3], std::atoi(argv[4]));
  if (argc != 3) {
    std::cerr << "usage: make_icc_press_photos SIDECAR PREFIX | --shrink IN OUT WIDTH\n";
    return 2;
  }
  const std::string sidecar = argv[1], prefix = argv[2];
  std::string calib_error, tags_error;
  cv::Mat page;
  double px_per_mm = 0;
  // The same resolutions as icc_press_test: finer than the photos' 3.9 px/mm.
  if (const auto layout = ReadCalibSidecar(sidecar, &calib_error)) {
    px_per_mm = 6.0;
    page = RasterizeCalibPage(*layout, px_per_mm);
  } else if (const auto record = ReadSidecar(sidecar, &tags_error)) {
    const auto images = RasterizeSheet(*record, 150.0, &tags_error);
    if (!images) {
      std::cerr << "make_icc_press_photos: " << tags_error << "\n";
      return 1;
    }
    page = images->pages[0];
    px_per_mm = images->px_per_mm;
  } else {
    std::cerr << "make_icc_press_photos: neither a calibration sheet (" << calib_error
              << ") nor a tag sheet (" << tags_error << ")\n";
    return 2;
  }
  std::string error;
  const auto press = testing::IccPress::Load(testing::IccPress::DefaultCmykProfilePath(), &error);
  if (!press) {
    std::cerr << "make_icc_press_photos: " << error << "\n";
    return 1;
  }
  for (const testing::NamedCamera& light : testing::TungstenAndDaylight()) {
    const std::string path = prefix + "-" + light.name + ".png";
    if (!cv::imwrite(path, testing::PrintAndPhotograph(page, px_per_mm, press->AsPrintFn(), {},
                                                       light.camera))) {
      std::cerr << "make_icc_press_photos: cannot write " << path << "\n";
      return 1;
    }
  }
  return 0;
}
