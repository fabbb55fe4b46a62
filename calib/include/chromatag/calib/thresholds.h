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
#include "chromatag/families/margins.h"

namespace chromatag {

// Readings of the palette's shades in one measured photo (index: Shade),
// `seen` through a detector with `white_balance` (DetectorOptions).
std::array<ShadeReading, kNumShades> ReadShades(const CalibSheetLayout& layout,
                                                const PhotoMeasurement& photo,
                                                const std::array<double, 3>& white_balance = {
                                                    1.0, 1.0, 1.0});

struct ThresholdOptions {
  // Every threshold keeps this factor between itself and the measured
  // margin (ADiffThresh = a* gap / factor, ...). [1, 10]. The default
  // (families/margins.h) leaves room for light, angle and blur the
  // calibration photos did not see.
  double safety_factor = kMarginSafetyFactor;
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
  double thin_adiff = 10.0;           // ADiffThresh: natural scenes seed near this.
  double thin_b_gap = kThinShadeGap;  // b* units between two shades.
  double thin_decision = 3.0;         // Expected decision margin.

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
