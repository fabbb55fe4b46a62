// Reading one patch's pixels out of a photo (measure.cc's first stage).
#ifndef CHROMATAG_CALIB_SRC_SAMPLE_PATCH_H_
#define CHROMATAG_CALIB_SRC_SAMPLE_PATCH_H_

#include <opencv2/core.hpp>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/measure.h"

namespace chromatag::internal {

struct PatchPixels {
  int pixels = 0;
  Rgb linear_mean;          // Trimmed mean per channel of the central square, linear light.
  Rgb inner_linear_mean;    // The same over the inner square.
  double clipped_high = 0;  // Fraction of pixels with a channel >= 254.
  double clipped_zero = 0;  // Fraction with a channel at 0.
  // Camera luminance (linear Y) percentiles of single pixels, untrimmed.
  double y_p02 = 0, y_p50 = 0, y_p98 = 0;
  double noise_a = 0, noise_b = 0;  // As-shot single-pixel spread.
};

// Samples the central square of `patch` (MeasureOptions::central_fraction of
// its side) in `bgr` through `image_from_page`.
PatchPixels SamplePatch(const cv::Mat& bgr, const cv::Matx33d& image_from_page, const Patch& patch,
                        const MeasureOptions& options);

}  // namespace chromatag::internal

#endif  // CHROMATAG_CALIB_SRC_SAMPLE_PATCH_H_
