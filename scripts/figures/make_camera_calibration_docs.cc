// Writes the synthetic views behind docs/camera-calibration.md (not a test):
// twenty views of a generated board through a 752 x 480 camera with fx 600
// and barrel distortion (k1 -0.25), noise, lens blur and JPEG, and a
// twenty-first with one tag misprinted (a copy of another board tag).
// Usage, after 'chromatag generate --board 6x4 --page 250x180mm --dpi 203.2
// -o DIR/board.png':
//   make_camera_calibration_docs DIR
// then 'chromatag calibrate-camera DIR/views --board DIR/board.png.json -o
// DIR/camera.yaml --report DIR/report.png'.
#include <filesystem>
#include <iostream>
#include <random>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "chromatag/layout/sheet_record.h"
#include "chromatag/rig/board_file.h"
#include "page_view.h"

namespace {

// The board with tag 9's square printed with tag 16's pattern.
chromatag::testing::PrintedPage Misprinted(const chromatag::testing::PrintedPage& page,
                                           const chromatag::SheetRecord& record) {
  chromatag::testing::PrintedPage shown = page;
  shown.bgr = page.bgr.clone();
  const auto box = [&](int i) {
    const auto& c = record.tags[i].corners_mm;
    return cv::Rect(cv::Point(static_cast<int>(c[0][0] * page.px_per_mm),
                              static_cast<int>(c[0][1] * page.px_per_mm)),
                    cv::Point(static_cast<int>(c[2][0] * page.px_per_mm),
                              static_cast<int>(c[2][1] * page.px_per_mm)));
  };
  page.bgr(box(16)).copyTo(shown.bgr(box(9)));
  return shown;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace chromatag;
  if (argc != 2) {
    std::cerr << "usage: make_camera_calibration_docs DIR (DIR holds board.png and "
                 "board.png.json from generate --board)\n";
    return 2;
  }
  const std::string dir = argv[1];
  std::string error;
  const auto record = ReadSidecar(dir + "/board.png.json", &error);
  const auto board = record ? BoardFromSheet(*record, &error) : std::nullopt;
  testing::PrintedPage page;
  page.bgr = cv::imread(dir + "/board.png");
  if (!board || page.bgr.empty()) {
    std::cerr << "make_camera_calibration_docs: "
              << (error.empty() ? "cannot read " + dir + "/board.png" : error) << "\n";
    return 2;
  }
  page.px_per_mm = page.bgr.cols / record->page.width_mm;
  page.origin_mm = record->board_origin_mm;
  const CameraIntrinsics camera = testing::BarrelCamera();
  cv::Vec3d centre(0, 0, 0);
  for (const BoardTag& tag : board->tags) centre += tag.translation / double(board->tags.size());
  std::filesystem::create_directories(dir + "/views");
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> tilt(10, 45), distance(0.2, 0.32), axis(0, 360),
      spin(-20, 20), side(-0.05, 0.05), blur(0.3, 1.0);
  for (int v = 0; v <= 20; ++v) {
    testing::PrintedPage shown = page;
    if (v == 20) shown = Misprinted(page, *record);
    cv::Vec3d rvec, tvec;
    const double t = tilt(rng), a = axis(rng), s = spin(rng), x = side(rng), y = side(rng);
    testing::PlaceBoard(centre, {x, y, distance(rng)}, t, a, s, &rvec, &tvec);
    testing::SceneOptions effects;
    effects.noise_sigma = 1.0;
    effects.blur_sigma = blur(rng);
    effects.blur_in_linear_light = true;
    effects.jpeg_quality = v % 3 == 0 ? 85 : 0;
    effects.seed = static_cast<unsigned>(v + 1);
    char name[64];
    std::snprintf(name, sizeof name, "/views/view%02d.png", v);
    if (!cv::imwrite(dir + name,
                     testing::PhotographPage(shown, camera, {752, 480}, rvec, tvec, effects))) {
      std::cerr << "make_camera_calibration_docs: cannot write " << dir << name << "\n";
      return 1;
    }
  }
  std::cout << "Wrote " << dir << "/views/view00.png ... view20.png (view20: tag 9 misprinted)\n";
  return 0;
}
