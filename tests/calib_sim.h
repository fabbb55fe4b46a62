// Synthetic photos of printed calibration sheets and tags for the calibration
// tests: a simulated printer (desaturation, hue shift, dot gain, a paper
// black) and a simulated camera (colour matrix, cast, exposure, uneven light,
// tone curve, perspective, blur, noise). The truth of every step is known.
#ifndef CHROMATAG_TESTS_CALIB_SIM_H_
#define CHROMATAG_TESTS_CALIB_SIM_H_

#include <array>
#include <functional>

#include <opencv2/core.hpp>

#include "chromatag/base/units.h"
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

  // A printer that loses four fifths of the chroma: the default palette's a*
  // gap of 115 prints as about 23, below the paper's ADiffThresh of 25.
  static SimPrinter WashedOut() { return {0.2, 4.0, 0.3, 18.0}; }
};

// Any printer: the printed colour (CIELAB relative to the paper white) of a
// sent 8-bit sRGB colour. SimPrinter::Print and IccPress::Print (icc_press.h)
// are two.
using PrintFn = std::function<Lab(const Rgb8&)>;

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

// How the printed page's content lands on the paper: scaled about the
// page's centre, as a print dialog's "fit to page" (0.97) or a printer's
// stretched axis (scale_y 1.01) puts it.
struct PrintGeometry {
  double scale_x = 1.0;
  double scale_y = 1.0;
};

// A flatbed scanner: the paper lies on the glass, a little crooked, and is
// imaged at exactly `dpi` with even light, a scanner's tone curve (sRGB),
// slight blur and noise. The glass around the paper is the lid's white.
struct SimScanner {
  double dpi = 300.0;
  // The paper's tilt on the glass about its top-left corner, counter-clockwise
  // as seen in the scan.
  double rotation_deg = 0.6;
  cv::Point2d offset_mm{4.0, 3.0};  // The page's top-left corner on the glass.
  double glass_width_mm = 222.0;
  double glass_height_mm = 305.0;
  double exposure = 0.92;  // Linear level of the paper white.
  double blur_sigma_px = 0.6;
  double noise_sigma = 1.0;  // 8-bit levels.
  unsigned seed = 1;
};

// A page raster (CV_8UC3 BGR of the sent colours at `page_px_per_mm`, e.g.
// from verify's RasterizeSheet) printed by `print` with `geometry`, then
// scanned by `scanner`: CV_8UC3 BGR at scanner.dpi.
cv::Mat PrintAndScan(const cv::Mat& page_bgr, double page_px_per_mm, const PrintFn& print,
                     const PrintGeometry& geometry, const SimScanner& scanner);

// Where page position `page_mm` (from the top-left corner of a page of
// `page_size_mm`, x right, y down) lands in PrintAndScan's scan, pixels with
// centres at integers: the print's scale about the page centre c, then the
// scanner's rotation R about the page's top-left corner and its offset,
// (R (S (p - c) + c) + offset) * dpi / 25.4 - 0.5.
cv::Point2d ScanPixelOfPagePoint(const cv::Point2d& page_mm, const cv::Size2d& page_size_mm,
                                 const PrintGeometry& geometry, const SimScanner& scanner);

// The same page printed and photographed by `camera` (its page_corners_px
// say where the page's corners land; uneven light as RenderSheetPhoto).
cv::Mat PrintAndPhotograph(const cv::Mat& page_bgr, double page_px_per_mm, const PrintFn& print,
                           const PrintGeometry& geometry, const SimCamera& camera);

// Where a page's corners land in a pinhole camera (square pixels, principal
// point at the centre, focal length f px) looking at the page's centre from
// `distance_mm`, the page turned by `tilt_deg` about its horizontal axis and
// `yaw_deg` about its vertical one: a perspective a real camera can make.
std::array<cv::Point2d, 4> PinholePageCorners(const PageSize& page, double f, double tilt_deg,
                                              double yaw_deg, double distance_mm, cv::Size size);

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
