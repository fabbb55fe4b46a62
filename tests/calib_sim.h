// Synthetic photos of printed calibration sheets and tags for the calibration
// tests: a simulated printer (desaturation, hue shift, dot gain, a paper
// black) and a simulated camera (colour matrix, cast, exposure, uneven light,
// tone curve, perspective, blur, noise). The truth of every step is known.
#ifndef CHROMATAG_TESTS_CALIB_SIM_H_
#define CHROMATAG_TESTS_CALIB_SIM_H_

#include <array>

#include <opencv2/core.hpp>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag::testing {

struct SimPrinter {
  double chroma_scale = 0.85;  // Printed chroma over the file's.
  double hue_shift_deg = 6.0;  // Printed hue minus the file's.
  double dot_gain = 0.25;      // Mid-tones darken: c' = 1 - (1 - c)^(1 / (1 + dot_gain)).
  double black_l = 12.0;       // L* of full ink; the paper is L* 100.

  // The printed colour of `sent`, CIELAB relative to the paper white.
  Lab Print(const Rgb8& sent) const;
};

struct SimCamera {
  // Linear sRGB -> camera linear RGB (rows summing to 1 keep white white).
  cv::Matx33d matrix = cv::Matx33d::eye();
  cv::Vec3d gains{1.0, 1.0, 1.0};  // Colour cast: R, G, B multipliers.
  double exposure = 0.85;          // Linear level of the paper white at the centre.
  double gamma = 0.0;              // 0: the sRGB curve; else encode with x^(1/gamma).
  double falloff = 0.2;            // Light lost at the page corners relative to the centre.
  double blur_sigma_px = 0.7;
  double noise_sigma = 1.5;  // 8-bit levels.
  int width = 1600;
  int height = 1200;
  // Where the page's corners land (top-left, top-right, bottom-right,
  // bottom-left), pixels: a mild keystone by default.
  std::array<cv::Point2d, 4> page_corners_px = {{{520, 50}, {1120, 80}, {1160, 1150}, {470, 1125}}};
  unsigned seed = 1;

  double Encode(double linear) const;
};

// Renders the sheet at `page_px_per_mm`, prints it with `printer`, and
// photographs it with `camera`: a CV_8UC3 BGR photo.
cv::Mat RenderSheetPhoto(const CalibSheetLayout& layout, const SimPrinter& printer,
                         const SimCamera& camera, double page_px_per_mm = 6.0);

// What `camera` reports for a flat patch of `printed` colour under even light,
// read as sRGB and normalised to the paper white the same way: the best any
// measurement through this camera can do.
Lab CameraReferredTruth(const Lab& printed, const SimCamera& camera);

// One tag printed by `printer` with `sent` colours, photographed face-on by
// `camera` (no perspective) on a light grey table, `cell_px` pixels a cell.
cv::Mat RenderPrintedTag(const TagFamily& family, int id, const TagColors& sent,
                         const SimPrinter& printer, const SimCamera& camera, double cell_px,
                         int width, int height);

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_CALIB_SIM_H_
