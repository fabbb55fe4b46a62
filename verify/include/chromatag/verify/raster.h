// Turning a generated sheet file back into pixels, as a printer or a viewer
// would: PDF through poppler, SVG through librsvg, PNG as it is.
#ifndef CHROMATAG_VERIFY_RASTER_H_
#define CHROMATAG_VERIFY_RASTER_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/layout/sheet_record.h"

namespace chromatag {

// The pages of a sheet, rasterised one at a time: memory holds one page
// however many the sheet has. Every page's size in pixels is known on Open,
// so a page too large for the resolution is refused before any is drawn.
class SheetPages {
 public:
  // Opens the sheet `record` describes, to rasterise its PDF or SVG pages at
  // `dpi` (a PNG keeps its own resolution, record.dpi). Refuses (nullopt,
  // *error) a missing or unreadable file, a page count other than the
  // sidecar's, and a page over kMaxImagePixels or 32767 pixels a side at
  // that resolution (the message gives the size and the highest dpi that
  // fits).
  static std::optional<SheetPages> Open(const SheetRecord& record, double dpi,
                                        std::string* error = nullptr);

  int size() const { return static_cast<int>(sizes_.size()); }
  double px_per_mm() const { return px_per_mm_; }
  // Width and height of page `index` in pixels, as Render will draw it.
  cv::Size page_size(int index) const { return sizes_.at(index); }

  // Rasterises page `index` (0-based) to CV_8UC3 BGR. Returns an empty Mat
  // and sets *error when the renderer fails (out of memory, a damaged page).
  // Not for two threads at once: a PDF's pages share one poppler document.
  cv::Mat Render(int index, std::string* error = nullptr) const;

 private:
  struct Source;
  std::shared_ptr<const Source> source_;
  std::vector<cv::Size> sizes_;
  double px_per_mm_ = 0.0;
};

// Every page of a sheet at once, for small sheets (tests, simulations):
// memory grows with the page count, so a tool that checks sheets of any
// length goes through SheetPages.
struct SheetImages {
  std::vector<cv::Mat> pages;  // CV_8UC3, BGR, one per page.
  double px_per_mm = 0.0;
};

// Rasterises every page through SheetPages (so it refuses what Open and
// Render refuse).
std::optional<SheetImages> RasterizeSheet(const SheetRecord& record, double dpi,
                                          std::string* error = nullptr);

// Converts a page position in millimetres (sidecar convention: from the
// page's top-left corner) to pixel coordinates (pixel centres at integers).
cv::Point2d MmToPixel(const std::array<double, 2>& mm, double px_per_mm);
std::array<double, 2> PixelToMm(const cv::Point2d& px, double px_per_mm);

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_RASTER_H_
