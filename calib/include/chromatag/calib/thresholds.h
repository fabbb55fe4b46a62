// The colour margins a printed palette leaves the detector, and detector
// thresholds derived from them (the calibration's step 3).
//
// The detector seeds on an a* rise above ADiffThresh (green to red), scans
// until pixels differ from the reference red by more than BorderThresh, and
// splits each colour's cells in b*, accepting the decode when the gap between
// the two groups is at least min_decision_margin times their spread.
#ifndef CHROMATAG_CALIB_THRESHOLDS_H_
#define CHROMATAG_CALIB_THRESHOLDS_H_

#include <array>
#include <string>
#include <vector>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/measure.h"
#include "chromatag/detector/options.h"

namespace chromatag {

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

// Readings of the palette's shades in one measured photo (index: Shade),
// `seen` through a detector with `white_balance` (DetectorOptions).
std::array<ShadeReading, kNumShades> ReadShades(const CalibSheetLayout& layout,
                                                const PhotoMeasurement& photo,
                                                const std::array<double, 3>& white_balance = {
                                                    1.0, 1.0, 1.0});

struct ThresholdOptions {
  // Every threshold keeps this factor between itself and the measured
  // margin (ADiffThresh = a* gap / factor, ...). [1, 10]. 2 leaves room for
  // light, angle and blur the calibration photos did not see.
  double safety_factor = 2.0;
  // The dimmest light, as a share of the calibration photos', in which the
  // tags must still be found. (0, 1]. a* scales with the cube root of the
  // light (CIELAB), so ADiffThresh is derived from the a* gap times
  // cbrt(dimmest_light): 0.3 keeps 0.67 of it, as in a dim room.
  double dimmest_light = 0.3;
  // Bounds for the derived values. ADiffThresh and the decision margin are
  // never raised above the detector's defaults: a higher ADiffThresh only
  // saves candidates and loses tags in dimmer light than the photos', and
  // a higher margin loses small and blurred tags (blur lowers the margins
  // the detector sees well below what a sharp photo of a patch shows)
  // without fewer wrong IDs (decode.cc's checks keep those out at the
  // default).
  double min_adiff = 4.0;
  double max_adiff = DetectorOptions{}.adiff_thresh;
  double min_border = 3.0;
  double min_decision_margin = 1.0;
  double max_decision_margin = DetectorOptions{}.min_decision_margin;
  // Below these the margin is reported as too thin to be trusted.
  double thin_adiff = 10.0;    // ADiffThresh: natural scenes seed near this.
  double thin_b_gap = 8.0;     // b* units between two shades.
  double thin_decision = 3.0;  // Expected decision margin.

  bool IsValid(std::string* error) const;
};

enum class Verdict { kGood, kThin, kFail };
const char* VerdictName(Verdict verdict);  // "good", "thin", "fail".

struct PairVerdict {
  std::string pair;  // "red-1 / red-0 (b*)", "green-1 / green-0 (b*)", "reds / greens (a*)".
  double worst_gap = 0.0;
  Verdict verdict = Verdict::kGood;
  std::string why;
};

struct DerivedThresholds {
  DetectorOptions options;  // Defaults except the derived fields.
  Margins worst;            // Over every photo and both views.
  std::vector<PairVerdict> verdicts;
  std::vector<std::string> warnings;  // Margins too thin to be trusted.
};

// Derives ADiffThresh, BorderThresh, min_decision_margin and max_green_a
// from the worst margins over `photos` (each: normalised and as the detector
// sees it);
// two_step_rises stays on, as in the detector's defaults.
DerivedThresholds DeriveThresholds(const std::vector<Margins>& per_photo_worst,
                                   const ThresholdOptions& options = {});

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_THRESHOLDS_H_
