// The colour margins a printed palette leaves the detector, from the shades
// as a camera saw them: how far the reds lie from the greens in a*, how far
// each colour's two shades lie apart in b* against the print's unevenness
// and the photo's noise. The colour calibration derives detector thresholds
// from them; the print check judges a print by them.
#ifndef CHROMATAG_FAMILIES_MARGINS_H_
#define CHROMATAG_FAMILIES_MARGINS_H_

#include <algorithm>
#include <array>

#include "chromatag/families/color.h"

namespace chromatag {

// How much a print's colours must have to spare, shared by the colour
// calibration (which keeps every derived threshold this factor inside the
// measured margin) and the print check (which warns below either): two
// shades of one colour closer than kThinShadeGap in b* are thin, and so is a
// margin under kMarginSafetyFactor times what the detector needs. The factor
// leaves room for light, angle and blur a photo of the print did not see.
inline constexpr double kThinShadeGap = 8.0;
inline constexpr double kMarginSafetyFactor = 2.0;

// One palette shade as measured in one photo: the mean over its usable
// repeats.
struct ShadeReading {
  Lab lab;      // White-normalised.
  Lab as_shot;  // As the camera delivered it.
  // As the detector sees it: the camera's colour through the detector's
  // white balance (as_shot when it has none).
  Lab seen;
  // Spread of b* between the repeats (standard deviation; print and light
  // unevenness) and of single pixels' a* and b* (the photo's noise).
  double repeat_spread_b = 0.0;
  double pixel_noise_a = 0.0;
  double pixel_noise_b = 0.0;
  int count = 0;
};

// Margins of the four chromatic shades (plus the paper white's L*).
struct Margins {
  double a_gap = 0.0;        // min a*(reds) - max a*(greens).
  double red_b_gap = 0.0;    // b*(red-1) - b*(red-0); negative: the shades are swapped.
  double green_b_gap = 0.0;  // b*(green-0) - b*(green-1).
  double a_spread = 0.0;     // Largest a* difference between the two shades of a colour.
  double min_red_a = 0.0;    // The paler red's a*: the detector wants 12 or more.
  double max_green_a = 0.0;  // The redder green's a* (DetectorOptions::max_green_a).
  double noise_a = 0.0;      // Single-pixel a* noise.
  double l_gap_white = 0.0;  // L*(white) - max L*(greens): the quiet zone's lead.
  // Expected decision margin: each colour's b* gap over its cell-level
  // spread (at least 1 b* unit, as the detector computes it), the smaller.
  double red_decision = 0.0;
  double green_decision = 0.0;

  double decision() const { return std::min(red_decision, green_decision); }
};

// Margins from four shade readings (red-1, red-0, green-1, green-0), the
// white's L* and whether to use the colours as the detector sees them
// (ShadeReading::seen) or the normalised ones.
Margins MarginsOf(const std::array<ShadeReading, 4>& shades, double white_l, bool seen);

// The worse of each member (smaller gaps, larger spreads and noise).
Margins Worst(const Margins& a, const Margins& b);

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_MARGINS_H_
