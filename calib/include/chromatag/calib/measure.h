// Measuring a photo of the calibration sheet: locate it, sample every patch
// robustly, flag the patches that cannot be trusted, and express the colours
// in CIELAB relative to the paper white (the calibration's step 1).
#ifndef CHROMATAG_CALIB_MEASURE_H_
#define CHROMATAG_CALIB_MEASURE_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/locate_sheet.h"
#include "chromatag/families/color.h"

namespace chromatag {

struct MeasureOptions {
  // Side of the sampled square over the patch's side, (0, 1). The rim is left
  // out: blur, misregistration and the printer's edge spread live there.
  double central_fraction = 0.6;
  // A smaller square whose mean must agree with the central one within
  // max_inner_delta_e (CIEDE2000); otherwise the patch is `blurred`. (0, central).
  double inner_fraction = 0.3;
  double max_inner_delta_e = 2.5;
  // Trimmed mean: this fraction of pixels is dropped at each end, per
  // channel. [0, 0.45].
  double trim = 0.2;
  // Fewer sampled pixels than this flags the patch `too-small`. >= 4.
  int min_pixels = 40;
  // A patch is `clipped` when more than max_clipped_fraction of its pixels
  // have a channel at 254 or above, or more than a quarter have one at 0.
  double max_clipped_fraction = 0.02;
  // `glare`: the brightest 2 % of a patch lie more than glare_tail (relative
  // to the local paper white's luminance) above its median, three times as
  // far as its darkest 2 % lie below; or a paper patch lies more than
  // max_white_residual (relative) above the white fitted through the others.
  double glare_tail = 0.08;
  double max_white_residual = 0.06;
  // Paper white darker than this (8-bit, brightest channel) is underexposed.
  int min_white_level = 60;
  // More flagged colour patches than this fraction rejects the photo. (0, 1].
  double max_flagged_fraction = 0.25;

  bool IsValid(std::string* error) const;
};

enum PatchFlag : uint32_t {
  kFlagClipped = 1u << 0,
  kFlagGlare = 1u << 1,
  kFlagBlurred = 1u << 2,
  kFlagTooSmall = 1u << 3,
};
// "clipped, glare", "" for none.
std::string FlagNames(uint32_t flags);

struct PatchMeasurement {
  int index = 0;  // Into CalibSheetLayout::patches.
  uint32_t flags = 0;
  int pixels = 0;  // Sampled (central square).
  // Trimmed mean of the gamma-encoded camera RGB, [0, 1].
  Rgb camera_rgb;
  // The camera RGB read as sRGB, as it is: what the detector sees.
  Lab as_shot;
  // Normalised to the paper white fitted at the patch's position (the
  // light's falloff and the colour cast removed): what was printed, as far
  // as this camera can tell.
  Lab lab;
  // Spread of single pixels' as-shot a* and b* (standard deviation): the
  // photo's noise at this patch.
  double noise_a = 0.0;
  double noise_b = 0.0;

  bool usable() const { return flags == 0; }
};

struct PhotoMeasurement {
  SheetLocation location;
  std::vector<PatchMeasurement> patches;  // In layout order.
  // Paper white, brightest channel, 8-bit: the exposure.
  double white_level = 0.0;
  int flagged = 0;  // Colour patches (not paper) with any flag.
};

// Locates the sheet and measures every patch. Refuses (nullopt, *error) a
// photo where the sheet is not found (see LocateSheet), is over- or
// underexposed, or where too many patches (or every patch of a palette
// shade) are flagged.
std::optional<PhotoMeasurement> MeasurePhoto(const cv::Mat& bgr, const CalibSheetLayout& layout,
                                             const MeasureOptions& options = {},
                                             const LocateOptions& locate = {},
                                             std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_MEASURE_H_
