// 1. FindADiff: advances along the cursor's row, sampling every N-th pixel,
// to the next sample whose a* rises by more than ADiffThresh over the previous
// sample of the row, skipping accepted areas. With it, the row schedule, the
// row scan and the rise tests it applies. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_FIND_ADIFF_H_
#define CHROMATAG_DETECTOR_SRC_FIND_ADIFF_H_

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/options.h"
#include "geometry.h"
#include "image_view.h"
#include "kernels/color_table.h"

namespace chromatag::internal {

// FindADiff's buffers: a sampled row's a* (or coarse a*) and the samples that
// may rise. The cursor points into `rises` until the row is done.
struct RowScanBuffers {
  std::vector<int32_t> a;
  std::vector<int> rises;
};

// An accepted detection's area, which FindADiff skips.
struct DetectedArea {
  Quad quad;  // The outer quad grown by one cell (the quiet zone).
  double min_y = 0, max_y = 0;
  // The range [x_begin, x_end] the area covers on row y; false if none.
  bool RowSpan(double y, double* x_begin, double* x_end) const;
  // Whether `p` lies in the area (its row span, edges included).
  bool Contains(cv::Point2d p) const {
    double begin = 0, end = 0;
    return RowSpan(p.y, &begin, &end) && begin <= p.x && p.x <= end;
  }
};

// FindADiff's position on its current sampled row. On the first call the
// whole row is sampled at once (SIMD where available) and the rises the
// prefilter lets through are listed (ScanRow); later calls walk that list.
struct RowCursor {
  int y = 0;
  // The row's place among the frame's `num_rows` sampled rows and the next
  // one's y (-1 after the last), for FindADiff's prefetches; SampledRow sets
  // them (a cursor without them prefetches nothing).
  int row = 0;
  int num_rows = 0;
  int next_y = -1;
  bool sampled = false;
  const int* rises = nullptr;  // Sample indices i that may rise from i - 1.
  int num_rises = 0;
  int next = 0;  // Next entry of `rises` to look at.
};

// The frame's sampled rows, y = 0, r, 2 r, ... below `height` (r =
// DetectorOptions::sampled_row_step): their number, and a cursor at the
// start of row number `row` of them. The one row schedule: Detect walks it,
// and FindADiff prefetches by it.
inline int NumSampledRows(int height, const DetectorOptions& options) {
  const int row_step = options.sampled_row_step();
  return (height + row_step - 1) / row_step;
}
inline RowCursor SampledRow(int height, const DetectorOptions& options, int row) {
  RowCursor cursor;
  cursor.row = row;
  cursor.num_rows = NumSampledRows(height, options);
  cursor.y = row * options.sampled_row_step();
  cursor.next_y = row + 1 < cursor.num_rows ? cursor.y + options.sampled_row_step() : -1;
  return cursor;
}

// How FindADiff's row scan finds the samples that may rise, by the kernels'
// path (kernels/kernels.h). Each is a conservative prefilter of the accurate
// rise (none is ever missed); they differ in speed and in how many false
// rises they let through:
// - with AVX-512 (VBMI) and N = 4: a* computed in 16-bit lanes
//   (ColorTable::FastA, within kFastAErrorBound), 32 samples at a time;
// - otherwise the coarse a* table, eight samples at a time with AVX2, else
//   one at a time.

// The rise in ColorTable::FastA units that the computed a* lets through: a
// true rise above `adiff_thresh` shows at least this much, as each of the two
// samples' FastA is within kFastAErrorBound of its accurate a*.
int ComputedARiseThreshold(double adiff_thresh);
// The FastA below which the computed a* takes a sample two back as green
// (SeedsAt): every sample whose accurate a* is below TwoStepGreenA.
int ComputedAGreenLimit(const DetectorOptions& options);
// The FastA above which it takes a sample as red enough to end such a rise:
// every sample whose accurate a* is at least kTwoStepCastMinRedA.
int ComputedATwoStepRedFloor();
// The FastY below which it takes a sample as dim enough for the lower bar
// (kDimTwoStepShare): every sample whose accurate L* is below
// kDimTwoStepMaxL, with room for FastY's error.
int ComputedDimYLimit();

// Whether FindADiff computes a* with these options and the view's kernels.
// Then its row scan does not read the coarse a* table, and FindADiff brings
// the table in for the later stages a few lines per sampled row
// (ColorTable::PrefetchCoarseLines) instead of Detect streaming it first.
bool RowScanComputesA(const ImageView& image, const DetectorOptions& options);

// FindADiff's second kind of rise (DetectorOptions::two_step_rises; not in
// the paper): sample i seeds when
// its a* rises by more than ADiffThresh over sample i - 2, that sample is
// green (a* below kTwoStepGreenA), and both steps rise by more than
// kTwoStepShare of ADiffThresh. A tag's red/green border blurred by the
// optics, demosaicing or JPEG's 4:2:0 chroma spreads over 8 px or more, and
// on a dim card or a washed-out print its step then falls into two samples
// each under ADiffThresh: an iccv17 print at 0.37 of the light under a
// tungsten cast reads a* -9, 12, 29 on three samples across a 135 px tag's
// border, and no sample seeded. Rises over two samples from grey or red
// (most of a natural scene's) do not count, nor does the sample after a
// one-step rise (its second step is flat), nor a sample short of
// kTwoStepMinRedA or darker than kTwoStepMinL: the rises of this kind in
// natural scenes mostly end weakly red or in the dark, where a* is noise.
// On 804 camera-set frames, outside the cards: 40.3 one-step rises a frame,
// 6.4 more of this kind; they seed 43 of the 45 tags of 30 px or more
// (up to 60 degrees) that no one-step rise seeded.
inline constexpr float kTwoStepGreenA = -4.f;
inline constexpr float kTwoStepShare = 0.25f;
inline constexpr float kTwoStepMinRedA = 18.f;
inline constexpr float kTwoStepMinL = 15.f;
// What a colour cast and dim light do to those levels: a faded red under a
// green cast and in dim light reads a* 10, a green under a magenta cast
// a* 0 or more. A rise over two samples from a green into a red paler than
// kTwoStepMinRedA but at least kTwoStepCastMinRedA seeds a candidate that
// must show a tag's colours in its own light before InitialScan spends a
// centring pass on it (Seed::kInACast); with DetectorOptions::cast_seeds,
// so does a rise from a green lifted up to kTwoStepCastGreenA. On 600 of
// the camera set's tag-free frames the pale reds took the mean time up by
// about 4 % and the lifted greens by about 14 % more; the pale reds found
// 22 more of the 140 tags of a faded print under strong casts in dim light
// (DetectorConditionsTest.StrongCastsOnAFadedPrintInDimLight), the lifted
// greens alone none more.
inline constexpr float kTwoStepCastGreenA = 3.f;
inline constexpr float kTwoStepCastMinRedA = 8.f;

// Dim light takes chroma with lightness: a tag at a third of the light
// keeps about two thirds of its a* (a* and L* scale alike, with the cube
// root of the light). A rise over two samples into a red darker than
// kDimTwoStepMaxL needs only kDimTwoStepShare of ADiffThresh, and seeds as
// a pale red does (Seed::kInACast). The camera set's JPEG-target tag (50 px,
// 0.34 of the light, 3.9 px of motion blur, JPEG 64, red at L* 30) rises by
// a* 24 over two samples against ADiffThresh 25. On the camera set's 2,033
// tag-free frames the lower bar adds 2.5 % of seeds; the AVX-512 row
// kernel reads the samples' luminance with their a* (ComputedDimYLimit), so
// that the rises into lighter reds do not reach the accurate test.
inline constexpr float kDimTwoStepMaxL = 40.f;
inline constexpr float kDimTwoStepShare = 0.9f;

// The green a rise over two samples starts from: the looser level with
// DetectorOptions::cast_seeds.
inline float TwoStepGreenA(const DetectorOptions& options) {
  return options.cast_seeds ? kTwoStepCastGreenA : kTwoStepGreenA;
}

// What a sample's rise is: none, a seed, or a seed only if the light is
// cast or dim (the looser levels above).
enum class Seed { kNone, kSeed, kInACast };

// The rise a sample (a*, L*) makes after a* `before` and `two_before` (the
// accurate test FindADiff applies; `two_before` NaN where there is none).
inline Seed SeedsAt(const DetectorOptions& options, LabF lab, float before, float two_before) {
  const float thresh = static_cast<float>(options.adiff_thresh);
  const float a = lab.a;
  if (a - before > thresh) return Seed::kSeed;
  if (!options.two_step_rises) return Seed::kNone;
  const float step = kTwoStepShare * thresh;
  const float total = lab.L < kDimTwoStepMaxL ? kDimTwoStepShare * thresh : thresh;
  if (!(two_before < kTwoStepCastGreenA && a - two_before > total && a - before > step &&
        before - two_before > step && a >= kTwoStepCastMinRedA && lab.L >= kTwoStepMinL)) {
    return Seed::kNone;
  }
  if (two_before < kTwoStepGreenA)
    return a >= kTwoStepMinRedA && a - two_before > thresh ? Seed::kSeed : Seed::kInACast;
  return options.cast_seeds ? Seed::kInACast : Seed::kNone;
}

// FindADiff's scan of sampled row y: fills `rises` (one entry per sample at
// most) with the indices i (x = i N) that may seed (SeedsAt: a* rising from
// sample i - 1 by more than ADiffThresh, or, with two_step_rises, from a
// green sample i - 2 in two steps), in order, and returns their number. `coarse` is
// scratch of one entry per sample.
int ScanRow(const ImageView& image, const DetectorOptions& options, int y, int32_t* coarse,
            int* rises);

// FindADiff: false at the row's end; else the seed and its kind (never
// kNone). *prefilter_rejects counts rises the row scan's prefilter suggested
// but the accurate a* refuted.
bool FindADiff(const ImageView& image, const DetectorOptions& options,
               const std::vector<DetectedArea>& skip, RowScanBuffers* buffers, RowCursor* cursor,
               cv::Point* seed, Seed* kind, int* prefilter_rejects);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_FIND_ADIFF_H_
