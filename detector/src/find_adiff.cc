// Stage 1, FindADiff (paper section 4): the only stage that touches the whole
// frame, so it is the one that sets the speed on frames without tags.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "stages.h"

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

bool FindADiff(const ImageView& image, const DetectorOptions& options,
               const std::vector<DetectedArea>& skip, RowCursor* cursor, cv::Point* seed,
               int* prefilter_rejects) {
  const ColorTable& table = image.table();
  const int8_t* coarse = table.coarse_a_table();
  const int step = options.step;
  const int width = image.width();
  const int r = image.r_offset(), b = image.b_offset();
  // The coarse table is within kCoarseErrorBound of the exact a*, so a true
  // rise above ADiffThresh shows at least this much in coarse values.
  const int coarse_thresh =
      static_cast<int>(std::floor(options.adiff_thresh)) - 2 * ColorTable::kCoarseErrorBound;
  const float adiff = static_cast<float>(options.adiff_thresh);
  const int y = cursor->y;
  const uint8_t* row = image.Pixel(0, y);
  std::array<std::pair<int, int>, 64> spans;
  const int num_spans = skip.empty() ? 0 : RowSpans(skip, y, &spans);

  int x = cursor->x;
  int old_a = cursor->old_coarse_a;
  bool has_old = cursor->has_old;
  int span = 0;
  while (x < width) {
    // The samples up to the next accepted area, or the row's end.
    while (span < num_spans && spans[span].second < x) ++span;
    int stop = width;
    if (span < num_spans) {
      if (spans[span].first <= x) {
        // MoveJToEndOfDetection: continue at the first grid column past the
        // area, with no previous sample to compare against.
        x = (spans[span].second + step) / step * step;
        has_old = false;
        continue;
      }
      stop = spans[span].first;
    }
    for (; x < stop; x += step) {
      const uint8_t* p = row + 3 * x;
      const int a = coarse[((p[r] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[b] >> 3)];
      if (has_old && a - old_a > coarse_thresh) {
        const uint8_t* q = p - 3 * step;
        const float exact_rise = table.A(p[r], p[1], p[b]) - table.A(q[r], q[1], q[b]);
        if (exact_rise > adiff) {
          cursor->x = x + step;
          cursor->old_coarse_a = a;
          cursor->has_old = true;
          *seed = cv::Point(x, y);
          return true;
        }
        ++*prefilter_rejects;
      }
      old_a = a;
      has_old = true;
    }
  }
  cursor->x = x;
  return false;
}

}  // namespace chromatag::internal
