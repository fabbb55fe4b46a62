// Choosing a palette from the printed candidates: the reds and greens whose
// worst-case a* gap and b* shade gaps, as printed and photographed, are the
// largest (the calibration's step 3).
#ifndef CHROMATAG_CALIB_PALETTE_CHOICE_H_
#define CHROMATAG_CALIB_PALETTE_CHOICE_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/measure.h"
#include "chromatag/families/palette.h"

namespace chromatag {

struct PaletteChoiceOptions {
  // The score is the smallest of the three margins, each over its goal (spec
  // section 6's recommended design values), as the palette design tool does:
  //   min(a* gap / a_goal, red b* gap / b_goal, green b* gap / b_goal).
  double a_goal = 80.0;
  double b_goal = 35.0;
  // Largest printed a* difference between the two shades of one colour,
  // worst case over photos: more and the detector's scans stop at shade
  // changes. > 0.
  double max_a_spread = 6.0;
  // Chosen colours must print at least this far in L* from black and from
  // the paper (the detector finds the green-black and white borders in L*).
  double min_l_from_black_and_white = 20.0;

  bool IsValid(std::string* error) const;
};

struct ChosenShade {
  Lab intended;               // The file colour written into the palette.
  int patch = -1;             // A candidate patch, or -1 for the sheet palette's own shade.
  std::vector<Lab> measured;  // Per photo, white-normalised.
};

struct PaletteChoice {
  Palette palette;                    // Black and white from the sheet's palette.
  std::array<ChosenShade, 4> shades;  // red-1, red-0, green-1, green-0.
  // Worst case over photos as printed and photographed (white-normalised).
  double a_gap = 0.0;
  double red_b_gap = 0.0;
  double green_b_gap = 0.0;
  double a_spread = 0.0;
  double score = 0.0;
  double sheet_palette_score = 0.0;  // The same score for the sheet's own palette.
  int combinations = 0;              // Candidate sets that met every constraint.
};

// Searches every pair of reds and pair of greens among the candidates and
// the sheet palette's own shades. Refuses (nullopt, *error) when no set meets
// the constraints (with the palette file's required checks).
std::optional<PaletteChoice> ChoosePalette(const CalibSheetLayout& layout,
                                           const std::vector<PhotoMeasurement>& photos,
                                           const PaletteChoiceOptions& options = {},
                                           std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_PALETTE_CHOICE_H_
