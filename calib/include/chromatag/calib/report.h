// The calibration report, drawn with Cairo: the a*b* plane with the targets
// against every photo's measurements, the margins and derived thresholds, a
// verdict for each shade pair, the chosen palette, and CIEDE2000 per patch
// (the printer model's residual) as a map of the sheet for every photo.
#ifndef CHROMATAG_CALIB_REPORT_H_
#define CHROMATAG_CALIB_REPORT_H_

#include <cairo.h>

#include <string>
#include <vector>

#include "chromatag/calib/calibrate.h"

namespace chromatag {

// Width of the report in Cairo user units (points in the PDF); the height
// grows with the number of photos.
inline constexpr double kReportWidth = 800.0;
double ReportHeight(const CalibrationResult& result);

// Draws the report at the current transform.
void DrawReport(cairo_t* cr, const CalibrationResult& result);

// One-page PDF on the calibration sheet's paper size (A4 unless the sheet
// was Letter, A3 or Legal), the report scaled to fit; and PNG at `scale`
// pixels per unit (1.5: 1200 pixels wide).
std::string RenderReportPdf(const CalibrationResult& result);
std::string RenderReportPng(const CalibrationResult& result, double scale = 1.5);

// The report's layout checked: every pair of labels (and legend swatches)
// whose boxes overlap, and labels running past the right edge; empty when
// the layout is clean.
std::vector<std::string> ReportOverlaps(const CalibrationResult& result);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_REPORT_H_
