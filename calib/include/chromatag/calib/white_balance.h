// The camera's white balance from photos of the calibration sheet: per
// photo, the linear-light gains that make the sheet's paper read neutral,
// and the one set all photos agree on, for the detector config
// (DetectorOptions::white_balance).
#ifndef CHROMATAG_CALIB_WHITE_BALANCE_H_
#define CHROMATAG_CALIB_WHITE_BALANCE_H_

#include <array>
#include <string>
#include <vector>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/measure.h"
#include "chromatag/families/color.h"

namespace chromatag {

// R, G, B gains on linear light, the largest 1 (DetectorOptions::white_balance).
using WhiteBalanceGains = std::array<double, 3>;

struct WhiteBalanceOptions {
  // The photos agree on one white balance when, through the gains they
  // share, no photo's paper keeps a cast (CIELAB chroma C*ab of its paper
  // white) above this. (0, 50]. Photos of the tests' simulated camera under
  // one light agree within 0.1; its tungsten lamp and daylight differ by
  // over 10. Beyond it the detector will not meet one light, and the config
  // holds no white balance.
  double max_residual_cast = 3.0;

  bool IsValid(std::string* error) const;
};

enum class WhiteBalanceOutcome {
  kWritten,    // The photos agree and the gains help: the config holds them.
  kDisagree,   // The photos were taken under different lights.
  kTooStrong,  // A gain would fall below kMinWhiteBalanceGain.
  // The light takes no a* from the reds: as shot, the finding margin
  // (FindingMargin) is larger than through the gains, which darken the
  // picture to the level of its weakest channel. Casts towards red or
  // magenta (a tungsten lamp) are such; towards green or blue, not.
  kNotNeeded,
};

struct WhiteBalance {
  WhiteBalanceOutcome outcome = WhiteBalanceOutcome::kWritten;
  bool written() const { return outcome == WhiteBalanceOutcome::kWritten; }
  // What the config holds: `shared` when written, else {1, 1, 1} (none).
  WhiteBalanceGains gains = {1.0, 1.0, 1.0};
  // Why it is not written, in a sentence with the numbers.
  std::string why;
  // The gains the photos share: the geometric mean of theirs, divided by
  // its largest, rounded to thousandths (the largest exactly 1).
  WhiteBalanceGains shared = {1.0, 1.0, 1.0};
  // Per photo: the gains that make its paper neutral, and the cast its paper
  // keeps through the shared gains (CIELAB a*, b* of the balanced white).
  std::vector<WhiteBalanceGains> per_photo;
  std::vector<Lab> residual;
  double worst_residual_cast = 0.0;  // The largest residual's chroma, C*ab.
  // The finding margin, worst over photos, as shot and through `shared`.
  double finding_margin_as_shot = 0.0;
  double finding_margin_balanced = 0.0;
};

// The gains that make `paper` (linear camera RGB) neutral, the largest 1.
WhiteBalanceGains GainsForWhite(const Rgb& paper);

// The paper white of a measured photo: the mean linear camera RGB of its
// usable paper patches.
Rgb PaperWhite(const CalibSheetLayout& layout, const PhotoMeasurement& photo);

// How much the sheet palette's colours, as a detector with `gains` sees them
// in `photo`, leave the detector to find a tag, in a* units: the smaller of
// the red-green a* gap and the paler red's a* above kMinTagRedA (below it
// the detector sees no red).
double FindingMargin(const CalibSheetLayout& layout, const PhotoMeasurement& photo,
                     const WhiteBalanceGains& gains);

// The white balance of `photos` (each measured on `layout`; `names` for
// messages, one per photo): each photo's gains and the gains they share,
// written when every photo's paper is neutral through them within
// options.max_residual_cast, they are within the detector's range
// (kMinWhiteBalanceGain) and the worst finding margin over the photos is
// no smaller through them than as shot.
WhiteBalance MeasureWhiteBalance(const CalibSheetLayout& layout,
                                 const std::vector<PhotoMeasurement>& photos,
                                 const std::vector<std::string>& names,
                                 const WhiteBalanceOptions& options = {});

// A colour (gamma-encoded camera RGB, as PatchMeasurement::camera_rgb) as a
// detector with `gains` sees it: each channel's linear light times its gain,
// in CIELAB.
Lab SeenThrough(const Rgb& camera_rgb, const WhiteBalanceGains& gains);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_WHITE_BALANCE_H_
