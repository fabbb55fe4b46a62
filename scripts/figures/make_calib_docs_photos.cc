// Writes the two synthetic photos behind docs/calibration.md's pictures (not
// a test). Usage, after 'chromatag calib-sheet -o DIR/calib.pdf':
//   make_calib_docs_photos DIR
// then 'chromatag calibrate DIR/warm.jpg DIR/dim.jpg --sheet DIR/calib.pdf.json -o DIR/out'.
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "calib_sim.h"
#include "chromatag/layout/calib_sheet_layout.h"

int main(int argc, char** argv) {
  using namespace chromatag;
  using chromatag::testing::RenderSheetPhoto;
  using chromatag::testing::SimCamera;
  using chromatag::testing::SimPrinter;
  if (argc != 2) {
    std::cerr << "usage: make_calib_docs_photos DIR (DIR holds calib.pdf.json from calib-sheet)\n";
    return 2;
  }
  const std::string dir = argv[1];
  std::string error;
  const auto layout = ReadCalibSidecar(dir + "/calib.pdf.json", &error);
  if (!layout) {
    std::cerr << "make_calib_docs_photos: " << error << "\n";
    return 2;
  }
  SimPrinter printer;  // Desaturates by 15 %, turns hues by 6 degrees, 25 % dot gain.
  SimCamera warm;
  warm.gains = {1.1, 1.0, 0.8};
  SimCamera dim;
  dim.exposure = 0.6;
  dim.gains = {0.9, 1.0, 1.1};
  dim.falloff = 0.3;
  dim.seed = 2;
  dim.page_corners_px = {{{560, 90}, {1180, 60}, {1130, 1140}, {520, 1170}}};
  const std::vector<int> jpeg = {cv::IMWRITE_JPEG_QUALITY, 92};
  const bool ok = cv::imwrite(dir + "/warm.jpg", RenderSheetPhoto(*layout, printer, warm), jpeg) &&
                  cv::imwrite(dir + "/dim.jpg", RenderSheetPhoto(*layout, printer, dim), jpeg);
  if (!ok) {
    std::cerr << "make_calib_docs_photos: cannot write into " << dir << "\n";
    return 1;
  }
  return 0;
}
