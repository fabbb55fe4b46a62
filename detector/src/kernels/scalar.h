// The scalar loops the vector kernels (kernels.h) must match to the last
// bit: a path without a vector kernel runs them, and the vector kernels run
// them on what is left over. Internal.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_SCALAR_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_SCALAR_H_

#include <algorithm>
#include <cstdint>

#include <opencv2/core.hpp>

#include "kernels/kernels.h"

namespace chromatag::internal {

// Nearest integer (halves round up), inline: std::lround is a library call,
// and the scans round two coordinates for every pixel they visit.
// `v` must lie within +-2^30 (the scans' coordinates do: a start inside the
// frame plus at most a frame's size of steps); no clamp here, where every
// scanned pixel passes (clamping cost 2 us of detector_bench's 51 us).
inline int RoundToInt(float v) {
  const float shifted = v + 0.5f;
  const int truncated = static_cast<int>(shifted);
  return truncated - (shifted < static_cast<float>(truncated) ? 1 : 0);
}
// For coordinates from a homography or a fit, which can be anything: values
// beyond +-2^30 (and NaN, taken as the lower bound) are clamped first, so
// that the casts are defined; such points lie outside any frame.
inline int RoundToInt(double v) {
  constexpr double kLimit = 1073741824.0;
  return RoundToInt(static_cast<float>(v > -kLimit ? (v < kLimit ? v : kLimit) : -kLimit));
}

// Whether sample i's value (coarse[i], after coarse[i - 1] and
// coarse[i - 2]) may seed by the sampler's thresholds (SeedsAt, each value
// within the table's error bound; the thresholds allow for it).
inline bool CoarseRiseAt(const RowSampler& s, const int32_t* coarse, int i) {
  const int rise = coarse[i] - coarse[i - 1];
  if (rise > s.threshold) return true;
  return i >= 2 && coarse[i - 2] < s.green_limit && coarse[i] > s.red_floor &&
         coarse[i] - coarse[i - 2] > s.dim_two_step_thresh && rise > s.step_thresh &&
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

// The gray (R + G + B) or R - G channel at sub-pixel (x, y), bilinear:
// ImageView::Sample's arithmetic for those channels. The caller checks
// PixelFrame::CanSample(x, y).
inline float SampleEdgeChannel(const PixelFrame& frame, bool gray, float x, float y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float tx = x - static_cast<float>(x0), ty = y - static_cast<float>(y0);
  const uint8_t* p = frame.Pixel(x0, y0);
  const uint8_t* q = p + frame.step;
  const int r = frame.r_offset, b = frame.b_offset;
  auto channel = [gray, r, b](const uint8_t* px) {
    return gray ? px[r] + px[1] + px[b] : px[r] - px[1];
  };
  const int c00 = channel(p), c01 = channel(p + 3), c10 = channel(q), c11 = channel(q + 3);
  const float top = static_cast<float>(c00) + static_cast<float>(c01 - c00) * tx;
  const float bottom = static_cast<float>(c10) + static_cast<float>(c11 - c10) * tx;
  return top + (bottom - top) * ty;
}

// Adds the grid's point k to *sums, unless it lies outside the frame.
inline void AddGridPoint(const PixelFrame& frame, const CellGrid& grid, int k, PixelSums* sums) {
  const double s = grid.spread[k % grid.samples], t = grid.spread[k / grid.samples];
  const cv::Point2d p = grid.centre + s * grid.du + t * grid.dv;
  const int x = RoundToInt(p.x), y = RoundToInt(p.y);
  if (!frame.Contains(x, y)) return;
  const uint8_t* px = frame.Pixel(x, y);
  sums->r += px[frame.r_offset];
  sums->g += px[1];
  sums->b += px[frame.b_offset];
  ++sums->n;
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_KERNELS_SCALAR_H_
