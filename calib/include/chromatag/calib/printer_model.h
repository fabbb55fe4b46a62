// A model of "RGB sent to the printer -> colour measured in the photo",
// fitted with Ceres (the calibration's step 2).
//
// Per channel a monotone tone curve (piecewise linear over kToneSegments equal
// steps of the gamma-encoded value, endpoints fixed at 0 and 1), then the sRGB
// transfer curve to linear light, then a 3x3 matrix and an offset to XYZ
// relative to the paper white, then CIELAB. The identity printer (what the
// file says is what is printed) is exactly the starting point: straight
// curves, the sRGB matrix, no offset. Tone curves absorb dot gain and the
// camera's tone; the matrix absorbs desaturation, hue shifts and casts; the
// offset is the ink's black.
#ifndef CHROMATAG_CALIB_PRINTER_MODEL_H_
#define CHROMATAG_CALIB_PRINTER_MODEL_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/families/color.h"

namespace chromatag {

inline constexpr int kToneSegments = 8;

struct PrinterModelOptions {
  // Residuals beyond this (CIELAB units) count linearly, not squared (Huber
  // loss): a patch the flags missed cannot drag the fit. > 0.
  double huber_delta = 3.0;
  // Weight of the tone curves' second differences (in log-slope). Keeps the
  // curves smooth where few patches constrain them. >= 0.
  double smoothness = 0.05;
  int max_iterations = 200;  // Levenberg-Marquardt iterations, >= 1.

  bool IsValid(std::string* error) const;
};

struct PrinterSample {
  Rgb sent;        // Gamma-encoded RGB sent to the printer, [0, 1].
  Lab measured;    // Relative to the paper white.
  int patch = -1;  // Where it came from (index into the sheet's patches).
};

class PrinterModel {
 public:
  PrinterModel();  // The identity printer.

  // Predicted measured colour of `sent` (gamma-encoded, [0, 1]).
  Lab Predict(const Rgb& sent) const;

  // The tone curve of one channel (0 = R) at `x` in [0, 1].
  double Tone(int channel, double x) const;

  // Parameters, for Ceres and for the report: log-increments of the curves,
  // the matrix (row-major, linear RGB -> XYZ) and the offset (XYZ).
  std::array<std::array<double, kToneSegments>, 3> tone{};
  std::array<double, 9> matrix{};
  std::array<double, 3> offset{};
};

// The sent RGB whose predicted colour is closest to `target` (least squares
// in CIELAB, summed over `models`), inside [0, 1]^3, from `start`. A target
// outside what the printer can reach gives the nearest colour it can.
Rgb InvertPrinter(const std::vector<PrinterModel>& models, const Lab& target, const Rgb& start);

struct PrinterFit {
  PrinterModel model;
  std::vector<double> residual_de;  // CIEDE2000 per sample, fitted vs measured.
  double mean_de = 0.0;
  double max_de = 0.0;
  int iterations = 0;
  bool converged = false;
};

// Fits the model to at least 20 samples. Refuses (nullopt, *error) fewer, or
// invalid options.
std::optional<PrinterFit> FitPrinterModel(const std::vector<PrinterSample>& samples,
                                          const PrinterModelOptions& options = {},
                                          std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_PRINTER_MODEL_H_
