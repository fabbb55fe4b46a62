// A sheet asked for in words, as the command line and the Python module take
// it ("0-9,12", "40mm", "a4", a palette name): one place that turns it into
// SheetOptions, so that both refuse the same things with the same messages.
#ifndef CHROMATAG_GENERATOR_SHEET_REQUEST_H_
#define CHROMATAG_GENERATOR_SHEET_REQUEST_H_

#include <string>

#include "chromatag/generator/sheet.h"

namespace chromatag {

struct SheetRequest {
  std::string family = "16h5";
  std::string ids;   // "0-9,12,20-27" (ParseIdList); empty with all = true.
  bool all = false;  // Every kept ID of the family.
  // Empty: 40 mm, or for a board the largest that fits the page.
  std::string size;
  std::string page = "a4";
  std::string margin = "10mm";  // "0" allowed, as for gap.
  std::string gap = "5mm";
  int quiet_zone = 2;
  bool cut_ring = false;
  bool crop_marks = false;
  bool label = true;
  bool one_per_page = false;
  std::string palette = "default";  // A built-in palette, unless palette_file is set.
  std::string palette_file;
  std::string color_lut;  // A .cube file, or empty.
  std::string format;     // "pdf", "svg", "png", or empty: from the output's extension.
  // A board: "COLSxROWS" (e.g. "6x4"), or empty for a sheet. Without IDs it
  // takes the family's first COLS * ROWS kept ones.
  std::string board;
  // Between a board's neighbouring black squares; empty: a quarter of the
  // tag size, or the quiet zone if that is wider.
  std::string spacing;
  double dpi = 300.0;
};

// Fills *options for writing to `output_path`; false with *error on bad
// input. A format that disagrees with the output's extension (a PNG named
// x.pdf) is refused.
bool ToSheetOptions(const SheetRequest& request, const std::string& output_path,
                    SheetOptions* options, std::string* error);

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_SHEET_REQUEST_H_
