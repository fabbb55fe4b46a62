// The blur model Decode checks 16h5 reads against (decode.cc): each cell's
// shade value is its shade's level plus a share of each of its four
// neighbours' levels, the black ring's included, the four levels fitted by
// least squares. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_BLUR_MODEL_H_
#define CHROMATAG_DETECTOR_SRC_BLUR_MODEL_H_

#include <limits>
#include <vector>

#include "chromatag/families/family.h"

namespace chromatag::internal {

// A cell as Decode reads it: the mean colour of its sampled middle.
struct CellSample {
  float a = 0;
  float shade = 0;  // b* + L* (decode.cc, kShadeLightness).
};

// The payload's cells and the black ring around them, (d + 2)^2 row by row,
// with the largest blur share (kBlurShares) the cells' size allows.
struct PayloadGrid {
  std::vector<CellSample> cells;
  float max_blur_share = 1.f;
  CellSample& operator[](int i) { return cells[i]; }
  const CellSample& operator[](int i) const { return cells[i]; }
};

// The neighbours' shares the model tries, up to the largest blur can carry
// into a cell's sampled middle (PayloadGrid::max_blur_share, plus one step;
// how they were chosen: decode.cc).
inline constexpr float kBlurShares[] = {0.f, 0.03f, 0.06f, 0.09f, 0.12f};

// What FitBlurModel makes of a pattern.
struct BlurFit {
  double worst = std::numeric_limits<double>::infinity();  // Worst cell over the gap.
  double rms = std::numeric_limits<double>::infinity();    // Root mean square over the gap.
  // At the blur share of the best rms: the smaller colour's gap between its
  // two shades' levels over the larger's.
  double gap_balance = 0;
  // The smallest root mean square misfit in shade units over every share,
  // the shades' order not asked for.
  double abs_rms = std::numeric_limits<double>::infinity();
};

// How far `pattern` (bits in the observed orientation) is from explaining
// the payload's shade values under blur: the smallest, over the blur shares,
// of the worst cell's misfit over the smaller shade gap; infinite if no share
// gives both colours' shades in their order. `grid`: the payload and the
// black ring around it, (d + 2)^2 cells row by row. With `merge_reds`, both
// reds are fitted as one level (a print whose reds print alike) and only the
// greens' gap is asked for.
BlurFit FitBlurModel(const TagFamily& family, Code pattern, const PayloadGrid& grid,
                     bool merge_reds = false);

// The least sum of squared misfits of `pattern` to the payload's shade
// values under the blur model (FitBlurModel's equations), over the blur
// shares, with each colour's shades in their order (red-1 at or above red-0,
// green-0 at or above green-1). Where the least-squares levels of a share
// are out of order, the constrained optimum lies on a bound: the reds as one
// level, the greens as one, or both, whichever in-order fit is best. Those
// are only fitted while the unconstrained misfit (never above them) is under
// `bound`: a result at or above `bound` says only that the misfit is.
double OrderedMisfit(const TagFamily& family, Code pattern, const PayloadGrid& grid,
                     double bound = std::numeric_limits<double>::infinity());

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_BLUR_MODEL_H_
