// Writes the simulated scans behind docs/verify.md's "Check your
// print" (not a test). Usage, after
// 'chromatag generate --family 16h5 --all --size 30mm -o DIR/tags.pdf':
//   make_print_check_docs DIR
// writes DIR/good-p1.png (page 1 through the SWOP press, scanned at 300 dpi),
// DIR/fit-p2.png (page 2 printed at 97 %), DIR/swapped-p3.png (page 3 with
// one tag's reds swapped).
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "calib_sim.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/raster.h"
#include "icc_press.h"

int main(int argc, char** argv) {
  using namespace chromatag;
  using namespace chromatag::testing;
  if (argc != 2) {
    std::cerr << "usage: make_print_check_docs DIR (DIR holds tags.pdf from generate)\n";
    return 2;
  }
  const std::string dir = argv[1];
  std::string error;
  const auto record = ReadSidecar(dir + "/tags.pdf.json", &error);
  const auto images = record ? RasterizeSheet(*record, 300.0, &error) : std::nullopt;
  const auto press = IccPress::Load(IccPress::DefaultCmykProfilePath(), &error);
  if (!images || !press || images->pages.size() < 3) {
    std::cerr << "make_print_check_docs: " << (error.empty() ? "need 3 pages" : error) << "\n";
    return 2;
  }
  const double px_per_mm = 300.0 / 25.4;
  // Page 3's first tag with red-1 and red-0 exchanged.
  cv::Mat swapped = images->pages[2].clone();
  const TagColors sent = TagColors::FromPalette(record->palette);
  const Rgb8 r1 = ToRgb8(sent[Shade::kRed1]), r0 = ToRgb8(sent[Shade::kRed0]);
  const PlacedTag* victim = nullptr;
  for (const PlacedTag& t : record->tags)
    if (t.page == 2 && !victim) victim = &t;
  const cv::Point2d tl = MmToPixel(victim->corners_mm[0], px_per_mm),
                    br = MmToPixel(victim->corners_mm[2], px_per_mm);
  for (int y = static_cast<int>(tl.y); y <= br.y; ++y) {
    for (int x = static_cast<int>(tl.x); x <= br.x; ++x) {
      cv::Vec3b& p = swapped.at<cv::Vec3b>(y, x);
      if (p == cv::Vec3b(r1.b, r1.g, r1.r))
        p = cv::Vec3b(r0.b, r0.g, r0.r);
      else if (p == cv::Vec3b(r0.b, r0.g, r0.r))
        p = cv::Vec3b(r1.b, r1.g, r1.r);
    }
  }
  const PrintFn print = press->AsPrintFn();
  SimScanner scanner;
  const bool ok =
      cv::imwrite(dir + "/good-p1.png",
                  PrintAndScan(images->pages[0], px_per_mm, print, {}, scanner)) &&
      cv::imwrite(dir + "/fit-p2.png",
                  PrintAndScan(images->pages[1], px_per_mm, print, {0.97, 0.97}, scanner)) &&
      cv::imwrite(dir + "/swapped-p3.png", PrintAndScan(swapped, px_per_mm, print, {}, scanner));
  if (!ok) {
    std::cerr << "make_print_check_docs: cannot write into " << dir << "\n";
    return 1;
  }
  return 0;
}
