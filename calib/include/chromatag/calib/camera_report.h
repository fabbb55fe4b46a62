// The camera calibration report, drawn with Cairo as Kalibr and calib.io
// show theirs: the parameters with their standard deviations and the
// warnings; the image's coverage by the used corners; every corner's
// residual as a vector where it lies and all residuals as a scatter; the
// rms of every view, and the views left out with why; on a second page,
// the projection check's maps (projection uncertainty and cross-validation
// over the image).
#ifndef CHROMATAG_CALIB_CAMERA_REPORT_H_
#define CHROMATAG_CALIB_CAMERA_REPORT_H_

#include <string>

#include "chromatag/calib/camera_calibration.h"

namespace chromatag {

// Two landscape A4 pages; `title` names the run (the board file, say).
std::string RenderCameraReportPdf(const CameraCalibration& calibration, const std::string& title);
// The same pages as one PNG, the second below the first, `scale` pixels
// per point (1.5: 1263 pixels wide, 1785 high).
std::string RenderCameraReportPng(const CameraCalibration& calibration, const std::string& title,
                                  double scale = 1.5);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CAMERA_REPORT_H_
