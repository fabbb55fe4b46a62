// `chromatag calibrate` as a library call: measure every photo of the
// calibration sheet, fit the printer per photo, measure the camera's white
// balance, derive detector thresholds, choose a palette, bake a printer LUT,
// and lay out the report.
#ifndef CHROMATAG_CALIB_CALIBRATE_H_
#define CHROMATAG_CALIB_CALIBRATE_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/base/output_files.h"
#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/camera_calibration.h"
#include "chromatag/calib/locate_sheet.h"
#include "chromatag/calib/measure.h"
#include "chromatag/calib/palette_choice.h"
#include "chromatag/calib/printer_model.h"
#include "chromatag/calib/thresholds.h"
#include "chromatag/calib/white_balance.h"

namespace chromatag {

struct CalibrateOptions {
  LocateOptions locate;
  MeasureOptions measure;
  PrinterModelOptions model;
  WhiteBalanceOptions white_balance;
  ThresholdOptions thresholds;
  PaletteChoiceOptions palette;
  int lut_size = 17;  // Grid of the .cube LUT per side, [2, 65].

  bool IsValid(std::string* error) const;
};

struct PhotoInput {
  std::string name;  // For messages and the report (the file name).
  cv::Mat bgr;       // CV_8UC3.
};

struct PhotoResult {
  std::string name;
  PhotoMeasurement measurement;
  PrinterFit fit;
  std::vector<int> fit_patches;  // Patch index of each of fit.residual_de.
  std::array<ShadeReading, kNumShades> shades;
  Margins normalised;  // The sheet palette's margins, white-normalised...
  // ...and as the calibrated detector sees them: through the config's white
  // balance (as the camera delivered them when it holds none).
  Margins seen;
};

struct CalibrationResult {
  CalibSheetLayout layout;
  CalibrateOptions options;
  std::vector<PhotoResult> photos;
  // The camera's white balance; thresholds.options.white_balance holds
  // white_balance.gains.
  WhiteBalance white_balance;
  DerivedThresholds thresholds;
  std::optional<PaletteChoice> palette;  // None if no candidate set qualifies.
  std::string palette_error;             // Why not, then.
  std::string cube;                      // .cube text.
  // Thin margins, a palette that could not be chosen, poor fits, photos
  // that disagree on the white balance.
  std::vector<std::string> warnings;
};

// Runs the whole calibration. A photo that cannot be used (sheet not found,
// part of it, another sheet, exposure, too many flagged patches) refuses the
// run: nullopt, and *error is "NAME: why".
std::optional<CalibrationResult> Calibrate(const CalibSheetLayout& layout,
                                           const std::vector<PhotoInput>& photos,
                                           const CalibrateOptions& options = {},
                                           std::string* error = nullptr);

// Camera intrinsics from the same photos, the sheet's corner tags as the
// board (BoardFromCalibSheet): taken at varied tilts, the photos that give
// the colours give the camera too. nullopt with *why when they cannot:
// fewer than three photos, photos of different sizes, fewer than three
// showing the tags, or the fit failed.
std::optional<CameraCalibration> CalibrateCameraFromPhotos(const CalibSheetLayout& layout,
                                                           const std::vector<PhotoInput>& photos,
                                                           std::string* why = nullptr);

// Output file names inside the output folder.
inline constexpr const char* kDetectorConfigFile = "detector.json";
inline constexpr const char* kPaletteFile = "palette.json";
inline constexpr const char* kLutFile = "printer.cube";
inline constexpr const char* kReportPdfFile = "report.pdf";
inline constexpr const char* kReportPngFile = "report.png";
inline constexpr const char* kMeasurementsFile = "measurements.json";
// Written when CalibrateCameraFromPhotos succeeds (OpenCV's layout).
inline constexpr const char* kCameraFile = "camera.yaml";

// The files to write into `folder` (for WriteFilesAtomically): the detector
// config (the derived thresholds, and the white balance when written), the
// palette (if one was chosen), the LUT, the report as PDF and PNG, and every
// measurement as JSON.
std::vector<OutputFile> CalibrationFiles(const CalibrationResult& result,
                                         const std::string& folder);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CALIBRATE_H_
