// Stage 1, FindADiff (paper section 4): the only stage that touches the whole
// frame, so it is the one that sets the speed on frames without tags.
#include "find_adiff.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "kernels/kernels.h"

namespace chromatag::internal {

bool DetectedArea::RowSpan(double y, double* x_begin, double* x_end) const {
  if (y < min_y || y > max_y) return false;
  double lo = 1e300, hi = -1e300;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d& p = quad[i];
    const cv::Point2d& q = quad[(i + 1) % 4];
    if ((p.y - y) * (q.y - y) > 0 || p.y == q.y) continue;
    const double x = p.x + (q.x - p.x) * (y - p.y) / (q.y - p.y);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  if (lo > hi) return false;
  *x_begin = lo;
  *x_end = hi;
  return true;
}

namespace {

// The row's stretches [begin, end] inside accepted areas, sorted.
int RowSpans(const std::vector<DetectedArea>& skip, int y,
             std::array<std::pair<int, int>, 64>* spans) {
  int n = 0;
  for (const DetectedArea& area : skip) {
    double begin = 0, end = 0;
    if (n < static_cast<int>(spans->size()) && area.RowSpan(y, &begin, &end)) {
      (*spans)[n++] = {static_cast<int>(std::ceil(begin)), static_cast<int>(std::floor(end))};
    }
  }
  std::sort(spans->begin(), spans->begin() + n);
  return n;
}

}  // namespace

int ComputedARiseThreshold(double adiff_thresh) {
  const double units =
      std::floor((adiff_thresh - 2 * ColorTable::kFastAErrorBound) * ColorTable::kFastAUnitsPerA);
  return static_cast<int>(std::clamp(units, -32768.0, 32767.0));
}

int ComputedATwoStepRedFloor() {
  return static_cast<int>(std::floor((kTwoStepCastMinRedA - ColorTable::kFastAErrorBound) *
                                     ColorTable::kFastAUnitsPerA));
}

int ComputedDimYLimit() {
  // FastY reads each channel at the centre of its top six bits, a few per
  // cent from the accurate Y; the limit sits 25 % above the Y of
  // kDimTwoStepMaxL (no colour darker than that is kept out, with or
  // without a white balance: FindADiffTwoStepTest.DimGateLetsEveryDimColourThrough).
  const double f = (kDimTwoStepMaxL + 16.0) / 116.0;
  return static_cast<int>(std::ceil(1.25 * f * f * f * 32768.0));
}

int ComputedAGreenLimit(const DetectorOptions& options) {
  return static_cast<int>(std::ceil((TwoStepGreenA(options) + ColorTable::kFastAErrorBound) *
                                    ColorTable::kFastAUnitsPerA));
}

bool RowScanComputesA(const ImageView& image, const DetectorOptions& options) {
  return options.step == 4 && image.kernels().scan_row_computed_a != nullptr;
}

int ScanRow(const ImageView& image, const DetectorOptions& options, int y, int32_t* coarse,
            int* rises) {
  const int step = options.step;
  const int count = (image.width() + step - 1) / step;
  // The row's samples; each path sets the table and thresholds of its units.
  RowSampler sampler;
  sampler.row = image.Pixel(0, y);
  sampler.row_bytes = 3 * image.width();
  sampler.count = count;
  sampler.pixel_step = 3 * step;
  sampler.r = image.r_offset();
  sampler.b = image.b_offset();
  if (RowScanComputesA(image, options)) {
    // The computed a* (ColorTable::FastA units) has thresholds of its own.
    sampler.threshold = ComputedARiseThreshold(options.adiff_thresh);
    sampler.step_thresh = ComputedARiseThreshold(kTwoStepShare * options.adiff_thresh);
    sampler.green_limit = options.two_step_rises ? ComputedAGreenLimit(options) : -32768;
    sampler.red_floor = ComputedATwoStepRedFloor();
    sampler.dim_two_step_thresh = ComputedARiseThreshold(kDimTwoStepShare * options.adiff_thresh);
    sampler.dim_y_limit = ComputedDimYLimit();
    return image.kernels().scan_row_computed_a(sampler, image.table().fast_a_tables(), rises);
  }
  // The coarse table is within kCoarseErrorBound of the accurate a*, so a
  // true rise above `accurate` shows at least this much in coarse values.
  auto coarse_rise = [](double accurate) {
    return static_cast<int>(std::floor(accurate)) - 2 * ColorTable::kCoarseErrorBound;
  };
  sampler.table = image.table().coarse_a_table();
  sampler.threshold = coarse_rise(options.adiff_thresh);
  sampler.step_thresh = coarse_rise(kTwoStepShare * options.adiff_thresh);
  // Without two_step_rises, no sample counts as green.
  sampler.green_limit =
      options.two_step_rises
          ? static_cast<int>(std::ceil(TwoStepGreenA(options))) + ColorTable::kCoarseErrorBound
          : INT_MIN;
  sampler.red_floor =
      static_cast<int>(std::floor(kTwoStepCastMinRedA)) - ColorTable::kCoarseErrorBound - 1;
  sampler.dim_two_step_thresh = coarse_rise(kDimTwoStepShare * options.adiff_thresh);
  return image.kernels().scan_row_coarse(sampler, coarse, rises);
}

namespace {

bool InSpans(const std::array<std::pair<int, int>, 64>& spans, int num_spans, int x) {
  for (int k = 0; k < num_spans; ++k) {
    if (spans[k].first <= x && x <= spans[k].second) return true;
  }
  return false;
}

}  // namespace

namespace {

// Samples the cursor's row (ScanRow) into the buffers and points the cursor
// at its rises. The next sampled row goes into the caches while this one
// is sampled: a frame from a camera or another thread is not in the
// caches, and the jump of several rows defeats the hardware's stream
// prefetch at each row's start.
void SampleCursorRow(const ImageView& image, const DetectorOptions& options,
                     RowScanBuffers* buffers, RowCursor* cursor) {
  const int count = (image.width() + options.step - 1) / options.step;
  if (buffers->a.size() < static_cast<size_t>(count)) {
    buffers->a.resize(count);
    buffers->rises.resize(count);
  }
  if (cursor->next_y >= 0) {
    const char* next = reinterpret_cast<const char*>(image.Pixel(0, cursor->next_y));
    const int bytes = 3 * image.width();
    for (int offset = 0; offset < bytes; offset += 64) __builtin_prefetch(next + offset);
  }
  if (cursor->num_rows > 0 && RowScanComputesA(image, options)) {
    // The coarse table, for the ring scans of this frame's seeds, spread
    // over the sampled rows (Detect did not stream it).
    const ColorTable& table = image.table();
    const int per_row = (table.coarse_lines() + cursor->num_rows - 1) / cursor->num_rows;
    table.PrefetchCoarseLines(cursor->row * per_row, per_row);
  }
  cursor->num_rises = ScanRow(image, options, cursor->y, buffers->a.data(), buffers->rises.data());
  cursor->rises = buffers->rises.data();
  cursor->next = 0;
  cursor->sampled = true;
}

// The kind of seed sample i of the row (at x = i N) is by the exact a*
// (SeedsAt): its rise from the sample before and, for the rise in two
// steps, from the one two back, unless that lies in an accepted area
// (`spans`).
Seed SeedKindAt(const ImageView& image, const DetectorOptions& options, const uint8_t* row, int i,
                const std::array<std::pair<int, int>, 64>& spans, int num_spans) {
  constexpr float kNoSample = std::numeric_limits<float>::quiet_NaN();
  const ColorTable& table = image.table();
  const int step = options.step;
  const int r = image.r_offset(), b = image.b_offset();
  const int x = i * step;
  const uint8_t* p = row + 3 * x;
  const uint8_t* q = p - 3 * step;
  const bool has_two =
      options.two_step_rises && i >= 2 && !(num_spans && InSpans(spans, num_spans, x - 2 * step));
  const float two_before =
      has_two ? table.A(q[r - 3 * step], q[1 - 3 * step], q[b - 3 * step]) : kNoSample;
  // L* only where the rise in two steps needs it.
  const LabF lab = two_before < TwoStepGreenA(options) ? table.Lab(p[r], p[1], p[b])
                                                       : LabF{0.f, table.A(p[r], p[1], p[b]), 0.f};
  return SeedsAt(options, lab, table.A(q[r], q[1], q[b]), two_before);
}

}  // namespace

bool FindADiff(const ImageView& image, const DetectorOptions& options,
               const std::vector<DetectedArea>& skip, RowScanBuffers* buffers, RowCursor* cursor,
               cv::Point* seed, Seed* kind, int* prefilter_rejects) {
  if (!cursor->sampled) SampleCursorRow(image, options, buffers, cursor);
  if (cursor->next >= cursor->num_rises) return false;
  const int step = options.step;
  const int y = cursor->y;
  const uint8_t* row = image.Pixel(0, y);
  std::array<std::pair<int, int>, 64> spans;
  const int num_spans = skip.empty() ? 0 : RowSpans(skip, y, &spans);
  while (cursor->next < cursor->num_rises) {
    const int i = cursor->rises[cursor->next++];
    const int x = i * step;
    // InPreviousDetectionArea: samples inside accepted areas are skipped, and
    // the first one past an area has no previous sample to compare against
    // (MoveJToEndOfDetection).
    if (num_spans && (InSpans(spans, num_spans, x) || InSpans(spans, num_spans, x - step))) {
      continue;
    }
    *kind = SeedKindAt(image, options, row, i, spans, num_spans);
    if (*kind != Seed::kNone) {
      *seed = cv::Point(x, y);
      return true;
    }
    ++*prefilter_rejects;
  }
  return false;
}

}  // namespace chromatag::internal
