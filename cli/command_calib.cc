// `chromatag calib-sheet` and `chromatag calibrate` (docs/calibration.md):
// input checking, library calls and output only.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "chromatag/base/input_file.h"
#include "chromatag/base/output_files.h"
#include "chromatag/base/units.h"
#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/calibrate.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/families/margins.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/cairo_util.h"
#include "chromatag/layout/calib_sheet_layout.h"
#include "chromatag/rig/camera_file.h"
#include "commands.h"

namespace chromatag::cli {
namespace {

struct CalibSheetArgs {
  std::string output;
  std::string palette = "default";
  std::string palette_file;
  std::string page = "a4";
  int sheet_id = 0;
  std::string tag_size = "20mm";
  std::string format;  // Empty: from the output's extension.
  double dpi = 300.0;
};

struct CalibrateArgs {
  std::vector<std::string> photos;
  std::string sheet;
  std::string output;
  double safety = kMarginSafetyFactor;
  int lut_size = 17;
};

std::string Extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

int RunCalibSheet(const CalibSheetArgs& args) {
  constexpr const char* kName = "calib-sheet";
  std::string error;
  CalibSheetOptions options;
  const auto palette = args.palette_file.empty() ? BuiltinPalette(args.palette, &error)
                                                 : LoadPaletteFile(args.palette_file, &error);
  if (!palette) return Fail(kName, error);
  options.palette = *palette;
  const auto page = ParsePageSize(args.page, &error);
  if (!page) return Fail(kName, error);
  options.page = *page;
  const auto tag_size = ParseLength(args.tag_size, &error);
  if (!tag_size) return Fail(kName, error);
  options.tag_size_mm = tag_size->mm;
  options.sheet_id = args.sheet_id;
  if (!IsValidUtf8(args.output))
    return Fail(kName, "the output name must be UTF-8 (the sidecar records it)");
  const std::string extension = Extension(args.output);
  const std::string format = args.format.empty() ? extension : args.format;
  if (format != "pdf" && format != "png") {
    return Fail(kName,
                "cannot tell the format of '" + args.output + "' (use .pdf or .png, or --format)");
  }
  if ((extension == "pdf" || extension == "png") && extension != format) {
    return Fail(kName, "the format is " + format + " but '" + args.output + "' names a " +
                           extension + " file: give the output a ." + format +
                           " name or leave the format out");
  }
  if (!(args.dpi >= 50 && args.dpi <= 1200)) return Fail(kName, "--dpi must be in [50, 1200]");
  if (format == "png") {
    const std::string problem =
        RasterPageProblem(options.page.width_mm, options.page.height_mm, args.dpi);
    if (!problem.empty()) return Fail(kName, "a PNG sheet: " + problem + "; lower --dpi");
  }
  const auto layout = LayoutCalibSheet(options, &error);
  if (!layout) return Fail(kName, error);
  const auto files =
      RenderCalibSheet(*layout, format == "pdf" ? CalibSheetFormat::kPdf : CalibSheetFormat::kPng,
                       args.output, args.dpi);
  if (!WriteFilesAtomically(files, &error)) return Fail(kName, error);
  int counts[4] = {0, 0, 0, 0};
  for (const Patch& p : layout->patches) ++counts[static_cast<int>(p.kind)];
  std::cout << "Wrote calibration sheet " << layout->sheet_id << " (palette "
            << layout->palette.name << ", page " << layout->page.name << "; corner tags "
            << layout->family << " " << layout->tags[0].id << ", " << layout->tags[1].id << ", "
            << layout->tags[2].id << ", " << layout->tags[3].id << "; " << layout->patches.size()
            << " patches: " << counts[1] << " palette, " << counts[3] << " candidate, " << counts[2]
            << " grey, " << counts[0] << " paper):\n";
  for (const auto& file : files) std::cout << "  " << file.path << "\n";
  std::cout << "Print at 100 % with colour management off, photograph the whole sheet, then run "
               "'chromatag calibrate PHOTO... --sheet "
            << files[1].path << " -o OUTDIR'.\n";
  return kExitOk;
}

void PrintSummary(const CalibrationResult& result, const std::vector<std::string>& written) {
  const DetectorOptions& d = result.thresholds.options;
  Print("Calibrated sheet %d from %zu photo(s):\n", result.layout.sheet_id, result.photos.size());
  for (const PhotoResult& p : result.photos) {
    Print(
        "  %s: %.1f px/mm, white %.0f/255, %d flagged patches, model CIEDE2000 mean %.2f "
        "max %.2f\n",
        p.name.c_str(), p.measurement.location.px_per_mm, p.measurement.white_level,
        p.measurement.flagged, p.fit.mean_de, p.fit.max_de);
  }
  Print(
      "Detector thresholds: ADiffThresh %.1f, BorderThresh %.1f, min decision margin "
      "%.2f, max green a* %.1f, two-step rises %s\n",
      d.adiff_thresh, d.border_thresh, d.min_decision_margin, d.max_green_a,
      d.two_step_rises ? "on" : "off");
  for (const PairVerdict& v : result.thresholds.verdicts)
    Print("  %-24s %-5s %s\n", v.pair.c_str(), VerdictName(v.verdict), v.why.c_str());
  const WhiteBalance& wb = result.white_balance;
  if (wb.written()) {
    Print(
        "White balance: R %.3f, G %.3f, B %.3f (gains on linear light; every photo's paper "
        "neutral within C*ab %.1f)\n",
        wb.gains[0], wb.gains[1], wb.gains[2], wb.worst_residual_cast);
  } else {
    Print("White balance: none written, %s\n", wb.why.c_str());
  }
  if (result.palette) {
    Print("Palette %s: score %.2f (sheet palette %.2f)\n", result.palette->palette.name.c_str(),
          result.palette->score, result.palette->sheet_palette_score);
  }
  for (const std::string& path : written) Print("  %s\n", path.c_str());
  std::fflush(stdout);
  for (const std::string& w : result.warnings) std::cerr << "warning: " << w << "\n";
}

// The camera calibrated from the photos, or why not (and an earlier run's
// camera file removed, as it is not from these photos).
void PrintCamera(const CameraCalibration* camera, const std::string& camera_why,
                 const std::string& output) {
  if (!camera) {
    const std::filesystem::path stale = std::filesystem::path(output) / kCameraFile;
    std::error_code ec;
    const bool removed =
        std::filesystem::is_regular_file(stale, ec) && std::filesystem::remove(stale, ec);
    Print("Camera intrinsics not written: %s%s\n", camera_why.c_str(),
          removed ? " (the earlier camera.yaml there is removed)" : "");
    return;
  }
  int used = 0;
  for (const CalibrationViewResult& v : camera->views) used += v.used ? 1 : 0;
  Print("Camera from %d of %zu photos: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.4f, rms %.3f px\n",
        used, camera->views.size(), camera->camera.fx, camera->camera.fy, camera->camera.cx,
        camera->camera.cy, camera->camera.distortion[0], camera->rms_px);
  for (const CalibrationViewResult& v : camera->views) {
    if (!v.used) Print("  %s left out: %s\n", v.name.c_str(), v.why_not.c_str());
  }
  std::fflush(stdout);
  for (const std::string& w : camera->warnings) std::cerr << "warning: camera: " << w << "\n";
}

int RunCalibrate(const CalibrateArgs& args) {
  constexpr const char* kName = "calibrate";
  std::string error;
  const auto layout = ReadCalibSheet(args.sheet, &error);
  if (!layout) return Fail(kName, error);
  CalibrateOptions options;
  options.thresholds.safety_factor = args.safety;
  options.lut_size = args.lut_size;
  if (!options.IsValid(&error)) return Fail(kName, error);
  std::vector<PhotoInput> photos;
  for (const std::string& path : args.photos) {
    cv::Mat image = ReadImage(path, &error);
    if (image.empty()) return Fail(kName, error);
    photos.push_back({path, image});
  }
  // Unusable photos fail the job (exit 1) and nothing is written.
  const auto result = Calibrate(*layout, photos, options, &error);
  if (!result) return Fail(kName, error, kExitFailure);
  std::error_code ec;
  // A folder made here and left empty by a failed write is removed again.
  const bool made = !std::filesystem::exists(args.output, ec);
  std::filesystem::create_directories(args.output, ec);
  if (ec) {
    return Fail(kName, "cannot create the output folder '" + args.output + "': " + ec.message());
  }
  const auto fail_written = [&](const std::string& why, int code) {
    std::error_code ignored;
    if (made && std::filesystem::is_empty(args.output, ignored))
      std::filesystem::remove(args.output, ignored);
    return Fail(kName, why, code);
  };
  auto files = CalibrationFiles(*result, args.output);
  // The camera from the same photos, when they were taken at varied tilts.
  std::string camera_why;
  const auto camera = CalibrateCameraFromPhotos(*layout, photos, &camera_why);
  if (camera) {
    CameraFileInfo info;
    info.image_size = camera->image_size;
    info.rms_px = camera->rms_px;
    std::string text = CameraFileText(camera->camera, info, CameraFileFormat::kOpenCv, &error);
    if (text.empty()) return fail_written(error, kExitFailure);
    files.push_back({(std::filesystem::path(args.output) / kCameraFile).string(), text});
  }
  if (!WriteFilesAtomically(files, &error)) return fail_written(error, kExitUsage);
  std::vector<std::string> written;
  for (const auto& file : files) written.push_back(file.path);
  PrintSummary(*result, written);
  PrintCamera(camera ? &*camera : nullptr, camera_why, args.output);
  return kExitOk;
}

}  // namespace

void RegisterCalib(CLI::App& app, Action* action) {
  auto s = std::make_shared<CalibSheetArgs>();
  CLI::App* sheet = app.add_subcommand(
      "calib-sheet", "Write a colour-calibration sheet (PDF or PNG) and its sidecar");
  sheet->add_option("-o,--output", s->output, "Output .pdf or .png; the sidecar goes beside it")
      ->required();
  auto* palette = sheet->add_option("--palette", s->palette, "Built-in palette: default, iccv17")
                      ->capture_default_str();
  sheet->add_option("--palette-file", s->palette_file, "Palette JSON file (docs/palettes.md)")
      ->excludes(palette);
  sheet->add_option("--page", s->page, "a4, a3, letter, legal, or WxH with a unit")
      ->capture_default_str();
  // 0 stands for "derived" inside; given on the command line it is refused,
  // not silently replaced by the derived ID.
  sheet->add_option("--sheet-id", s->sheet_id, "Sheet ID 1-65535 (default: from palette and page)")
      ->check(CLI::Range(1, 65535));
  sheet->add_option("--tag-size", s->tag_size, "Corner tags' black square, 10-60 mm")
      ->capture_default_str();
  sheet->add_option("--format", s->format, "pdf or png (default: from the output's extension)")
      ->check(CLI::IsMember({"pdf", "png"}));
  sheet->add_option("--dpi", s->dpi, "PNG resolution in pixels per inch")->capture_default_str();
  sheet->callback([s, action] { *action = [s] { return RunCalibSheet(*s); }; });

  auto c = std::make_shared<CalibrateArgs>();
  CLI::App* cal = app.add_subcommand(
      "calibrate",
      "Measure photos of a printed calibration sheet; write detector thresholds, a palette, a "
      "printer LUT and a report");
  cal->add_option("photos", c->photos, "Photos of the printed sheet (one per lighting)")
      ->required();
  cal->add_option("--sheet", c->sheet,
                  "The sheet from 'chromatag calib-sheet' (.pdf, .png; its sidecar beside it) or "
                  "its sidecar .json")
      ->required();
  cal->add_option("-o,--output", c->output, "Output folder (created if missing)")->required();
  cal->add_option("--safety", c->safety, "Safety factor between margins and thresholds, 1-10")
      ->capture_default_str();
  cal->add_option("--lut-size", c->lut_size, "Grid points per side of the .cube LUT, 2-65")
      ->capture_default_str();
  cal->callback([c, action] { *action = [c] { return RunCalibrate(*c); }; });
}

}  // namespace chromatag::cli
