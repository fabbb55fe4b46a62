// Finding the calibration sheet in a photo through its four corner tags.
#ifndef CHROMATAG_CALIB_LOCATE_SHEET_H_
#define CHROMATAG_CALIB_LOCATE_SHEET_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/calib/calib_sheet.h"

namespace chromatag {

struct LocateOptions {
  // Detector thresholds tried in turn, {ADiffThresh, BorderThresh} in a*
  // units, until all four corner tags are found: the sheet is printed by the
  // very printer being calibrated, so a washed-out print may need lower
  // thresholds than the paper's 25 and 5 to be found at all.
  std::vector<std::array<double, 2>> threshold_ladder = {
      {25.0, 5.0}, {15.0, 8.0}, {10.0, 5.0}, {8.0, 12.0}};
  // When the ladder fails on the photo as it is, it is tried again on a copy
  // white-balanced on the paper with a* and b* multiplied by this, [1, 5]:
  // the detector ignores reds below a* 12, which a washed-out print in dim
  // light can be. The copy is used to find the tags only, never to measure.
  double enhance_chroma = 2.0;
  // Largest root-mean-square distance, mm on the sheet, between the detected
  // tag corners and where the fitted homography puts them. (0, 10]. Beyond
  // it the sheet is not flat or the lens distorts too much for one
  // homography.
  double max_rms_mm = 1.0;

  bool IsValid(std::string* error) const;
};

struct SheetLocation {
  // Maps page millimetres (x right, y down from the top-left corner) to image
  // pixels (pixel centres at integers).
  cv::Matx33d image_from_page;
  double rms_mm = 0.0;     // Fit residual over the 16 tag corners.
  double px_per_mm = 0.0;  // Mean scale of the sheet in the photo.
  // The thresholds that found the tags (a rung of LocateOptions's ladder).
  double adiff_thresh = 0.0;
  double border_thresh = 0.0;
  bool enhanced = false;  // Found in the enhanced copy.
};

// Finds the four corner tags of `layout` in `bgr` (CV_8UC3, BGR) and fits
// the page-to-image homography. Returns nullopt with *error for: no tag at
// all, tags of another sheet (a different sheet ID), only some of the four
// (part of the sheet), or corners that do not fit one plane.
std::optional<SheetLocation> LocateSheet(const cv::Mat& bgr, const CalibSheetLayout& layout,
                                         const LocateOptions& options = {},
                                         std::string* error = nullptr);

// Image position of a page position.
cv::Point2d PageToImage(const cv::Matx33d& image_from_page, const std::array<double, 2>& mm);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_LOCATE_SHEET_H_
