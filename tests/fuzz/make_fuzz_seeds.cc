// Writes the seed corpora of the value_parsers, print_sidecar, sheet_raster,
// locate_sheet and video harnesses (tests/fuzz/corpus/<name>/) through the
// toolkit's own generator, so that every seed is an input the toolkit makes
// or reads for real. Not run by `make fuzz`; rerun it when the generator's
// output changes:
//   cmake --build build-fuzz --target make_fuzz_seeds
//   build-fuzz/tests/fuzz/make_fuzz_seeds tests/fuzz/corpus
// It checks what the harnesses rely on: the print_sidecar scan shows its
// four tags, and the calibration photo is located.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "chromatag/calib/locate_sheet.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/generator/sheet.h"
#include "fuzz_sheets.h"

namespace chromatag::fuzz {
namespace {

namespace fs = std::filesystem;

void Write(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
  std::cout << path.string() << ": " << bytes.size() << " bytes\n";
}

[[noreturn]] void Die(const std::string& why) {
  std::cerr << "make_fuzz_seeds: " << why << "\n";
  std::exit(1);
}

std::vector<OutputFile> Render(const SheetOptions& options, const std::string& output) {
  std::string error;
  auto files = RenderSheet(options, output, &error);
  if (!files) Die(output + ": " + error);
  return *files;
}

void ValueParserSeeds(const fs::path& dir) {
  auto ids = [](const char* family, size_t count) {
    const auto& kept = TagFamily::Load(family)->kept_ids();
    return FormatIdRanges({kept.begin(), kept.begin() + count});
  };
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"length_mm", "40mm"},        {"length_in", "1.5in"},        {"length_cm", " 4 cm "},
      {"length_m", "0.25m"},        {"page_named", "Letter"},      {"page_wxh", "210x297mm"},
      {"page_units", "8.5inx11in"}, {"ids_16h5", ids("16h5", 10)}, {"ids_36h11", ids("36h11", 40)}};
  for (const auto& [name, text] : seeds) Write(dir / name, text);
}

// The sidecars of the print_sidecar harness's page, as every layout writes
// it: the PNG scan itself, a PDF, a board and one tag per page.
void PrintSidecarSeeds(const fs::path& dir) {
  SheetOptions png = PrintSheet();
  Write(dir / "scan_png.json", Render(png, "sheet.png").back().contents);
  Write(dir / "pdf.json", Render(PrintSheet(SheetFormat::kPdf), "sheet.pdf").back().contents);
  SheetOptions board = PrintSheet(SheetFormat::kPdf);
  board.board = BoardGrid{2, 2, 4.0};
  board.label = false;
  Write(dir / "board.json", Render(board, "board.pdf").back().contents);
  SheetOptions pages = PrintSheet(SheetFormat::kSvg);
  pages.one_per_page = true;
  Write(dir / "one_per_page.json", Render(pages, "pages.svg").back().contents);

  // What the harness relies on: its scan shows the four tags.
  std::string error;
  const cv::Mat scan = DecodeImage(Render(png, "sheet.png")[0].contents, "scan", &error);
  DetectorOptions detector_options;
  detector_options.families = {"16h5"};
  auto detector = Detector::Create(detector_options, &error);
  if (scan.empty() || !detector) Die(error);
  const DetectionResult found = detector->Detect(scan, PixelOrder::kBgr);
  std::cout << "print_sidecar scan " << scan.cols << " x " << scan.rows << ": "
            << found.detections.size() << " tags\n";
  if (found.detections.size() != png.ids.size()) Die("the scan does not show its tags");
}

// One labelled tag on a small page: small files, with text in them.
void SheetRasterSeeds(const fs::path& dir) {
  for (SheetFormat format : {SheetFormat::kPdf, SheetFormat::kSvg}) {
    SheetOptions options = PrintSheet(format);
    options.ids.resize(1);
    options.page = {"custom", 30.0, 50.0};
    options.label = true;
    const std::string name = std::string("sheet.") + SheetFormatName(format);
    Write(dir / name, Render(options, name)[0].contents);
  }
}

std::string Encode(const char* ext, const cv::Mat& image, const std::vector<int>& params = {}) {
  std::vector<uchar> bytes;
  if (!cv::imencode(ext, image, bytes, params)) Die(std::string("cannot encode ") + ext);
  return {bytes.begin(), bytes.end()};
}

// Photos of the calibration sheet: face on, lossless and JPEG, and tilted.
void LocateSheetSeeds(const fs::path& dir) {
  std::string error;
  const auto layout = LayoutCalibSheet(CalibSheet(), &error);
  if (!layout) Die(error);
  const cv::Mat page = RasterizeCalibPage(*layout, kCalibPxPerMm);
  const float w = static_cast<float>(page.cols), h = static_cast<float>(page.rows);
  const cv::Matx33d tilt = cv::getPerspectiveTransform(
      std::vector<cv::Point2f>{{0, 0}, {w, 0}, {w, h}, {0, h}},
      std::vector<cv::Point2f>{{12, 5}, {w - 4, 14}, {w - 16, h - 6}, {3, h - 20}});
  cv::Mat tilted;
  cv::warpPerspective(page, tilted, tilt, page.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                      cv::Scalar(60, 70, 80));
  Write(dir / "sheet.png", Encode(".png", page));
  Write(dir / "sheet.ppm", Encode(".ppm", page));
  Write(dir / "sheet.jpg", Encode(".jpg", page, {cv::IMWRITE_JPEG_QUALITY, 92}));
  Write(dir / "tilted.jpg", Encode(".jpg", tilted, {cv::IMWRITE_JPEG_QUALITY, 85}));
  for (const cv::Mat& photo : {page, tilted}) {
    if (!LocateSheet(photo, *layout, {}, &error))
      Die("the calibration photo is not located: " + error);
  }
  std::cout << "locate_sheet photo " << page.cols << " x " << page.rows << ": located\n";
}

// Short clips of the print_sidecar page in the codecs OpenCV's FFmpeg
// writes to AVI here (MJPEG, and lossless FFV1 when it has it).
void VideoSeeds(const fs::path& dir) {
  std::string error;
  const cv::Mat scan = DecodeImage(Render(PrintSheet(), "sheet.png")[0].contents, "scan", &error);
  if (scan.empty()) Die(error);
  cv::Mat frame;
  cv::resize(scan, frame, {160, 160}, 0, 0, cv::INTER_AREA);
  const std::string temp = "/tmp/chromatag-fuzz-seed-" + std::to_string(getpid()) + ".avi";
  for (const auto& [name, fourcc] :
       {std::pair{"mjpeg.avi", cv::VideoWriter::fourcc('M', 'J', 'P', 'G')},
        std::pair{"ffv1.avi", cv::VideoWriter::fourcc('F', 'F', 'V', '1')}}) {
    {
      cv::VideoWriter writer(temp, fourcc, 10.0, frame.size());
      if (!writer.isOpened()) {
        std::cout << name << ": no writer for this codec, skipped\n";
        continue;
      }
      for (int i = 0; i < 3; ++i) {
        cv::Mat shifted;
        cv::warpAffine(frame, shifted, cv::Matx23d(1, 0, 2.0 * i, 0, 1, i), frame.size(),
                       cv::INTER_LINEAR, cv::BORDER_REPLICATE);
        writer.write(shifted);
      }
    }
    std::ifstream in(temp, std::ios::binary);
    Write(dir / name, std::string(std::istreambuf_iterator<char>(in), {}));
    std::remove(temp.c_str());
  }
}

}  // namespace
}  // namespace chromatag::fuzz

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_fuzz_seeds CORPUS_FOLDER (tests/fuzz/corpus)\n";
    return 2;
  }
  const std::filesystem::path root = argv[1];
  using namespace chromatag::fuzz;
  ValueParserSeeds(root / "value_parsers");
  PrintSidecarSeeds(root / "print_sidecar");
  SheetRasterSeeds(root / "sheet_raster");
  LocateSheetSeeds(root / "locate_sheet");
  VideoSeeds(root / "video");
  return 0;
}
