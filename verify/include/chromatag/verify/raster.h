// Turning a generated sheet file back into pixels, as a printer or a viewer
// would: PDF through poppler, SVG through librsvg, PNG as it is.
#ifndef CHROMATAG_VERIFY_RASTER_H_
#define CHROMATAG_VERIFY_RASTER_H_

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/generator/sidecar.h"

namespace chromatag {

struct SheetImages {
  std::vector<cv::Mat> pages;  // CV_8UC3, BGR, one per page.
  double px_per_mm = 0.0;
};

// Rasterises every page of the sheet `record` describes at `dpi` (PDF, SVG;
// a PNG keeps its own resolution, record.dpi). Refuses (nullopt, *error) a
// missing or unreadable file, or one with a different number of pages.
std::optional<SheetImages> RasterizeSheet(const SheetRecord& record, double dpi,
                                          std::string* error = nullptr);

// Converts a page position in millimetres (sidecar convention: from the
// page's top-left corner) to pixel coordinates (pixel centres at integers).
cv::Point2d MmToPixel(const std::array<double, 2>& mm, double px_per_mm);
std::array<double, 2> PixelToMm(const cv::Point2d& px, double px_per_mm);

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_RASTER_H_
