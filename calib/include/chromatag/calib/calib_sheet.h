// The colour-calibration sheet: four ChromaTags in the corners to
// find the sheet in a photo, the palette's colours repeated across the page,
// a grey ramp, bare-paper patches for the white, and a grid of candidate reds
// and greens around the palette, all in a pseudo-random order fixed by the
// sheet ID. Page coordinates are millimetres from the page's top-left corner,
// x to the right, y down, as in the generator's sidecar.
#ifndef CHROMATAG_CALIB_CALIB_SHEET_H_
#define CHROMATAG_CALIB_CALIB_SHEET_H_

#include <cairo.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/base/output_files.h"
#include "chromatag/base/units.h"
#include "chromatag/families/color.h"
#include "chromatag/families/palette.h"
#include "chromatag/layout/calib_sheet_layout.h"

namespace chromatag {

struct CalibSheetOptions {
  Palette palette;  // Its colours are printed and its reds and greens seed the candidates.
  PageSize page{"a4", 210.0, 297.0};
  // Sheet ID, printed on the sheet, recorded in the sidecar, and the seed of
  // both the patch order and the corner tags' IDs. [1, 65535]; 0 derives one
  // from the palette and the page, so the same inputs give the same sheet.
  int sheet_id = 0;
  // Side of the corner tags' black squares, mm. [10, 60]. 20 mm tags are
  // found by the detector down to about 3 pixels per millimetre on the sheet.
  double tag_size_mm = 20.0;
  // Side of a colour patch and the white gap between patches, mm. Patches of
  // [6, 40] mm; the sampler reads the central 60 %, so 12 mm patches give
  // 7 mm of colour clear of blur and misregistration. Gap [1, 20] mm.
  double patch_mm = 12.0;
  double gap_mm = 3.0;
  // Blank border on every side, mm. [3, 50].
  double margin_mm = 10.0;
  // Times each palette colour (red-1, red-0, green-1, green-0, black) appears
  // at least; slots left over after the candidates take more. [2, 20].
  int palette_repeats = 5;
  // Grey ramp: this many levels strictly between black and white, evenly
  // spaced in gamma-encoded sRGB. [3, 20].
  int grey_levels = 9;
  // Candidate grid per colour: a* offsets from the palette's a* and the b*
  // span beyond the palette's two shades, CIELAB units; b* is stepped
  // evenly in `candidate_b_steps` values. Candidates outside sRGB are dropped.
  std::vector<double> candidate_a_offsets = {-16.0, -8.0, 0.0, 8.0, 16.0};
  double candidate_b_reach = 16.0;
  int candidate_b_steps = 9;

  bool IsValid(std::string* error) const;
};

// Lays the sheet out. Refuses (nullopt, *error) invalid options and a page
// too small for the grid, saying how much room it needs.
std::optional<CalibSheetLayout> LayoutCalibSheet(const CalibSheetOptions& options,
                                                 std::string* error = nullptr);

// Draws the page with Cairo in millimetre user units (the caller scales).
// The corner tags go through the generator's DrawTag.
void DrawCalibPage(cairo_t* cr, const CalibSheetLayout& layout);

// The page as 8-bit BGR pixels at `px_per_mm` (pixel centres at integers),
// what a perfect printer and scanner would give. For tests and previews.
cv::Mat RasterizeCalibPage(const CalibSheetLayout& layout, double px_per_mm);

enum class CalibSheetFormat { kPdf, kPng };

// The sheet as a PDF (vector) or PNG (at `dpi`) and its sidecar beside it
// ("calib.pdf" -> "calib.pdf.json"), in memory, for WriteFilesAtomically.
// Byte-identical for identical layouts.
std::vector<OutputFile> RenderCalibSheet(const CalibSheetLayout& layout, CalibSheetFormat format,
                                         const std::string& output_path, double dpi = 300.0);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CALIB_SHEET_H_
