// Constants and helpers shared by the sheet layout, renderer and sidecar.
#ifndef CHROMATAG_GENERATOR_SRC_SHEET_INTERNAL_H_
#define CHROMATAG_GENERATOR_SRC_SHEET_INTERNAL_H_

#include <string>

#include "chromatag/generator/sheet.h"

namespace chromatag::internal {

// Height kept at the bottom of every page, above the margin, for the scale
// bar and the line of text that explains it, mm.
inline constexpr double kScaleStripMm = 14.0;
// Crop marks start this far from the tag's outer corner and end at kReach.
inline constexpr double kCropMarkGapMm = 1.0;
inline constexpr double kCropMarkReachMm = 4.0;
inline constexpr double kLabelLineFactor = 1.6;
// A board keeps this band left of and below its tags' quiet zones for the
// axes marked on the print, mm.
inline constexpr double kBoardAxesMm = 9.0;

std::string Mm(double mm);  // "40.0"
double LabelFontMm(const SheetOptions& options);
double LabelHeightMm(const SheetOptions& options);
double MarksMm(const SheetOptions& options);
double OuterMm(const SheetOptions& options);  // Tag with quiet zone and cut ring.
double QuietZoneMm(const SheetOptions& options);
// The page's room for tags: inside the margins and above the scale strip;
// with `turned`, of the page turned a quarter.
struct UsableMm {
  double width = 0.0, height = 0.0;
};
UsableMm Usable(const SheetOptions& options, bool turned = false);

// The record the sidecar of a rendered sheet holds (sidecar.cc).
SheetRecord SheetRecordOf(const SheetOptions& options, const SheetLayout& layout,
                          const std::vector<OutputFile>& page_files);

}  // namespace chromatag::internal

#endif  // CHROMATAG_GENERATOR_SRC_SHEET_INTERNAL_H_
