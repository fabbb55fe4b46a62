// The sheets that the harnesses draw their fixed images from and that
// make_fuzz_seeds draws their seeds from: one definition, so that a seed
// sidecar describes exactly the page the print_sidecar harness "scans", and
// a seed photo shows exactly the calibration sheet locate_sheet looks for.
#ifndef CHROMATAG_TESTS_FUZZ_FUZZ_SHEETS_H_
#define CHROMATAG_TESTS_FUZZ_FUZZ_SHEETS_H_

#include <cstdlib>
#include <string>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/sheet.h"

namespace chromatag::fuzz {

// Resolution of the print_sidecar harness's scan: low, so that detecting
// in it takes milliseconds, yet 4.7 px per 16h5 cell.
inline constexpr double kScanDpi = 100.0;

// Four 16h5 tags of 12 mm, 2 x 2 on a 70 mm square page (unlabelled: a
// label would push the second row to a page of its own), as a PNG at
// kScanDpi (a 276 x 276 px image). Aborts if the generator refuses it: the harness
// would otherwise fuzz nothing.
inline SheetOptions PrintSheet(SheetFormat format = SheetFormat::kPng) {
  SheetOptions options;
  options.family = TagFamily::Load("16h5");
  options.ids.assign(options.family->kept_ids().begin(), options.family->kept_ids().begin() + 4);
  options.palette = *BuiltinPalette("default");
  options.tag_size_mm = 12.0;
  options.page = {"custom", 70.0, 70.0};
  options.margin_mm = 5.0;
  options.gap_mm = 4.0;
  options.label = false;
  options.format = format;
  options.dpi = kScanDpi;
  if (!options.IsValid(nullptr)) std::abort();
  return options;
}

// A calibration sheet small enough to be seen whole in a 256 x 256 photo
// at 3 px/mm (locate_sheet's size limit): the smallest corner tags (10 mm,
// 5 px per cell) and patches the options allow.
inline constexpr double kCalibPxPerMm = 3.0;
inline CalibSheetOptions CalibSheet() {
  CalibSheetOptions options;
  options.palette = *BuiltinPalette("default");
  options.page = {"custom", 84.0, 84.0};
  options.sheet_id = 7;
  options.tag_size_mm = 10.0;
  options.patch_mm = 6.0;
  options.gap_mm = 1.0;
  options.margin_mm = 3.0;
  options.palette_repeats = 2;
  options.grey_levels = 3;
  options.candidate_a_offsets = {0.0};
  options.candidate_b_steps = 2;
  if (!options.IsValid(nullptr)) std::abort();
  return options;
}

}  // namespace chromatag::fuzz

#endif  // CHROMATAG_TESTS_FUZZ_FUZZ_SHEETS_H_
