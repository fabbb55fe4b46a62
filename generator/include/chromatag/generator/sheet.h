// Print-ready sheets of ChromaTags at exact physical size: layout, rendering
// to PDF, SVG or PNG with Cairo, and the JSON sidecar that records what was
// printed where (docs/generator.md).
#ifndef CHROMATAG_GENERATOR_SHEET_H_
#define CHROMATAG_GENERATOR_SHEET_H_

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/base/output_files.h"
#include "chromatag/base/units.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/color_lut.h"
#include "chromatag/generator/tag_renderer.h"
#include "chromatag/layout/sheet_record.h"

namespace chromatag {

struct SheetOptions {
  std::shared_ptr<const TagFamily> family;
  std::vector<int> ids;  // Kept IDs, in the order they are laid out.
  Palette palette;       // Written as sRGB, through `color_lut` if set.
  std::shared_ptr<const ColorLut> color_lut;

  // Side of the black square (spec section 1), mm. > 0.
  double tag_size_mm = 40.0;
  PageSize page{"a4", 210.0, 297.0};
  // Blank border kept on every side of the page, mm. >= 0; printers need ~5.
  double margin_mm = 10.0;
  // Space between neighbouring tags' footprints (quiet zone, marks and label
  // included), mm. >= 0.
  double gap_mm = 5.0;
  TagDrawOptions tag;  // Quiet zone (>= 1 cell, default 2) and cut ring.
  bool crop_marks = false;
  bool label = true;  // "16h5  ID 3  40 mm" under each tag.
  bool one_per_page = false;
  // Lay the tags out as a board (ids.size() == columns * rows; no per-tag
  // labels, cut rings or crop marks).
  std::optional<BoardGrid> board;

  SheetFormat format = SheetFormat::kPdf;
  // PNG resolution, pixels per inch. [10, 4800].
  double dpi = 300.0;

  bool IsValid(std::string* error) const;
};

// Page coordinates are millimetres from the page's top-left corner, y down
// (PlacedTag: chromatag/layout/sheet_record.h).
struct SheetLayout {
  int num_pages = 0;
  int columns = 0;  // Grid per page (1 x 1 with one_per_page).
  int rows = 0;
  double footprint_width_mm = 0.0;  // One tag with quiet zone, cut ring, marks, label.
  double footprint_height_mm = 0.0;
  double scale_bar_mm = 0.0;  // Length of the scale-check bar.
  std::vector<PlacedTag> tags;
  // The board frame's origin in page coordinates: the bottom-left corner of
  // the bottom-left tag's black square for a board, else the page's
  // bottom-left corner. Its x axis points right, y up the page, z out of it.
  std::array<double, 2> board_origin_mm{0.0, 0.0};
};

// The largest tag size (mm, rounded down to 0.1 mm, or to 1 mm from 10 mm)
// for which `options.board` fits its page with the given spacing, or with
// a spacing of `spacing_share` of the tag size when spacing_share > 0.
// Nullopt (and *error) when not even a 1 mm tag fits.
std::optional<double> BoardTagSizeToFit(const SheetOptions& options, double spacing_share,
                                        std::string* error = nullptr);

// Places the tags. Refuses (nullopt, *error) options that are not valid or a
// tag that does not fit the page, saying how much room it needs and has.
std::optional<SheetLayout> LayoutSheet(const SheetOptions& options, std::string* error = nullptr);

// Renders and writes the sheet to `output_path` (pages after the first of an
// SVG or PNG go to "<stem>-2.svg", ...) and its sidecar "<stem>.json", all or
// nothing (WriteFilesAtomically). Returns false with *error on any failure.
// On success, *written (if given) lists the files written, sidecar last.
bool WriteSheet(const SheetOptions& options, const std::string& output_path,
                std::string* error = nullptr, std::vector<std::string>* written = nullptr);

// The files WriteSheet would write for `output_path`, in memory: the page
// files then the sidecar. Output is byte-identical for identical options.
std::optional<std::vector<OutputFile>> RenderSheet(const SheetOptions& options,
                                                   const std::string& output_path,
                                                   std::string* error = nullptr);

// The RGB written for each shade: the palette as 8-bit sRGB, through the
// colour LUT if one is set (rounded to 8 bits again).
TagColors SheetColors(const SheetOptions& options);

// Guesses the format from the extension (.pdf, .svg, .png, any case).
std::optional<SheetFormat> FormatFromPath(const std::string& path, std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_SHEET_H_
