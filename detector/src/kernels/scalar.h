// The scalar loops the vector kernels (kernels.h) must match to the last
// bit: a path without a vector kernel runs them, and the vector kernels run
// them on what is left over. Internal.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_SCALAR_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_SCALAR_H_

#include <algorithm>
#include <cstdint>

#include "decode.h"
#include "image_view.h"
#include "kernels/kernels.h"

namespace chromatag::internal {

// Whether sample i's value (coarse[i], after coarse[i - 1] and
// coarse[i - 2]) may seed by the sampler's thresholds (SeedsAt, each value
// within the table's error bound; the thresholds allow for it).
inline bool CoarseRiseAt(const RowSampler& s, const int32_t* coarse, int i) {
  const int rise = coarse[i] - coarse[i - 1];
  if (rise > s.threshold) return true;
  return i >= 2 && coarse[i - 2] < s.green_limit && coarse[i] > s.red_floor &&
         coarse[i] - coarse[i - 2] > s.threshold && rise > s.step_thresh &&
         coarse[i - 1] - coarse[i - 2] > s.step_thresh;
}

// The coarse a* of samples [first, count).
void CoarseRowScalar(const RowSampler& s, int first, int32_t* coarse);
// Appends to rises[n ..] the samples i in [max(1, first), end) that may
// seed; returns the new count.
int RisesScalar(const RowSampler& s, int first, int end, const int32_t* coarse, int* rises, int n);
// Kernels::scan_row_coarse, one sample at a time.
int ScanRowCoarseScalar(const RowSampler& s, int32_t* coarse, int* rises);

// The gray channel (R + G + B, 0 to 765) in linear light: the three values'
// mean decoded with sRGB's curve (exact for neutral pixels, as black and
// white are), linearly interpolated between whole values (LinearGray and
// the AVX2 kernel read the same table with the same arithmetic).
const float* LinearGrayTable();
inline float LinearGray(float gray) {
  const float* table = LinearGrayTable();
  const float x = std::min(std::max(gray, 0.f), 765.f);
  const int i = static_cast<int>(x);
  return table[i] + (x - static_cast<float>(i)) * (table[i + 1] - table[i]);
}

// Adds the grid's point k to *sums, unless it lies outside the frame.
inline void AddGridPoint(const ImageView& image, const CellGrid& grid, int k, PixelSums* sums) {
  const double s = grid.spread[k % grid.samples], t = grid.spread[k / grid.samples];
  const cv::Point2d p = grid.centre + s * grid.du + t * grid.dv;
  const int x = RoundToInt(p.x), y = RoundToInt(p.y);
  if (!image.Contains(x, y)) return;
  const uint8_t* px = image.Pixel(x, y);
  sums->r += image.R(px);
  sums->g += image.G(px);
  sums->b += image.B(px);
  ++sums->n;
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_KERNELS_SCALAR_H_
