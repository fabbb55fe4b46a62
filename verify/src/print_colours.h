// The print check's colour measurement (print_check.h): a printed tag's
// payload cells read from the image through the homography of its black
// square, normalised to the paper white of its own quiet zone, and summed up
// per shade; and, where no tag of the sheet decoded, what the undecoded
// candidates' cells show.
#ifndef CHROMATAG_VERIFY_SRC_PRINT_COLOURS_H_
#define CHROMATAG_VERIFY_SRC_PRINT_COLOURS_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/families/family.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/print_check.h"

namespace chromatag::internal {

// The four shades of the tag of `family` whose black square lies at
// `corners` (spec order) in `bgr` (CV_8UC3), printed with `code`: each its
// cells' mean in CIELAB normalised to the quiet zone's white and as shot,
// their spread and pixel noise, and the margins between them. `measured` is
// false when a cell or too much of the quiet zone falls outside the image.
PrintedShades ReadPrintedShades(const cv::Mat& bgr, const std::array<cv::Point2d, 4>& corners,
                                const TagFamily& family, int quiet_zone_cells, Code code);

// The candidates of `result` the detector gave up on at Decode, each read
// as a tag of `record`'s family: how far its red and its green cells' b*
// split and its reds' a* lies from its greens'.
std::vector<UndecodedCandidate> Undecoded(const cv::Mat& bgr, const DetectionResult& result,
                                          const SheetRecord& record);

}  // namespace chromatag::internal

#endif  // CHROMATAG_VERIFY_SRC_PRINT_COLOURS_H_
