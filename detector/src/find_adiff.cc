// Stage 1, FindADiff (paper section 4): the only stage that touches the whole
// frame, so it is the one that sets the speed on frames without tags.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "avx2_kernels.h"
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

// Coarse a* of the samples x = 0, N, 2N, ... of one row, and the samples
// whose coarse a* rises from the previous one by more than `threshold`: the
// whole row at once, so that the frame-wide work is a plain array loop.
struct RowSampler {
  const uint8_t* row;
  int count;       // Samples on the row.
  int pixel_step;  // Bytes between samples: 3 N.
  int r, b;        // Byte offsets of red and blue in a pixel.
  const int8_t* table;
  int threshold;
};

void CoarseRowScalar(const RowSampler& s, int first, int32_t* coarse) {
  const uint8_t* p = s.row + static_cast<ptrdiff_t>(first) * s.pixel_step;
  for (int i = first; i < s.count; ++i, p += s.pixel_step)
    coarse[i] = s.table[((p[s.r] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[s.b] >> 3)];
}

int RisesScalar(const RowSampler& s, int first, const int32_t* coarse, int* rises, int n) {
  for (int i = std::max(1, first); i < s.count; ++i) {
    if (coarse[i] - coarse[i - 1] > s.threshold) rises[n++] = i;
  }
  return n;
}

#ifdef CHROMATAG_HAVE_AVX2_PATHS
// Eight samples per step: a gather of each sample's 3 bytes (as a 32-bit word;
// the fourth byte is ignored), the table index from shifts and masks, a
// gather from the coarse table (padded for the 32-bit reads); then eight
// differences per compare. Compiled for AVX2 alone and called only when the
// CPU has it.
__attribute__((target("avx2"))) int SampleRowAvx2(const RowSampler& s, int32_t* coarse,
                                                  int* rises) {
  // A word read at a sample reaches one byte past its pixel: the row's last
  // sample is left to the scalar loop.
  const int vector_count = s.count - 1;
  const __m256i offsets = _mm256_mullo_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
                                             _mm256_set1_epi32(s.pixel_step));
  const CoarseALookup lookup = MakeCoarseALookup(s.r, s.table);
  const __m256i pick_low =
      _mm256_setr_epi8(0, 1, 2, -1, 12, 13, 14, -1, -1, -1, -1, -1, -1, -1, -1, -1, 0, 1, 2, -1, 12,
                       13, 14, -1, -1, -1, -1, -1, -1, -1, -1, -1);
  const __m256i pick_high =
      _mm256_setr_epi8(-1, -1, -1, -1, -1, -1, -1, -1, 0, 1, 2, -1, 12, 13, 14, -1, -1, -1, -1, -1,
                       -1, -1, -1, -1, 0, 1, 2, -1, 12, 13, 14, -1);
  const __m256i in_order = _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7);
  int i = 0;
  for (; i + 8 <= vector_count; i += 8) {
    const int* base =
        reinterpret_cast<const int*>(s.row + static_cast<ptrdiff_t>(i) * s.pixel_step);
    __m256i words;
    if (s.pixel_step == 12) {
      // N = 4: two samples in each 16-byte load, picked into 32-bit lanes
      // by byte shuffles (cheaper than a gather); lanes hold samples
      // 0 1 4 5 | 2 3 6 7 and are put in order after the table lookup.
      const uint8_t* bytes = reinterpret_cast<const uint8_t*>(base);
      const __m256i first =
          _mm256_set_m128i(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 24)),
                           _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes)));
      const __m256i second =
          _mm256_set_m128i(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 72)),
                           _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 48)));
      words = _mm256_or_si256(_mm256_shuffle_epi8(first, pick_low),
                              _mm256_shuffle_epi8(second, pick_high));
    } else {
      words = _mm256_i32gather_epi32(base, offsets, 1);
    }
    __m256i a = CoarseA8(lookup, words);
    if (s.pixel_step == 12) a = _mm256_permutevar8x32_epi32(a, in_order);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(coarse + i), a);
  }
  CoarseRowScalar(s, i, coarse);
  int n = 0;
  const __m256i threshold = _mm256_set1_epi32(s.threshold);
  int j = 1;
  for (; j + 8 <= s.count; j += 8) {
    const __m256i rise =
        _mm256_sub_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j)),
                         _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j - 1)));
    unsigned mask = static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(rise, threshold))));
    while (mask) {
      rises[n++] = j + __builtin_ctz(mask);
      mask &= mask - 1;
    }
  }
  return RisesScalar(s, j, coarse, rises, n);
}
#endif

// Fills `coarse` and `rises`; returns the number of rises.
int SampleRow(const RowSampler& s, int32_t* coarse, int* rises) {
#ifdef CHROMATAG_HAVE_AVX2_PATHS
  if (CpuHasAvx2()) return SampleRowAvx2(s, coarse, rises);
#endif
  CoarseRowScalar(s, 0, coarse);
  return RisesScalar(s, 1, coarse, rises, 0);
}

bool InSpans(const std::array<std::pair<int, int>, 64>& spans, int num_spans, int x) {
  for (int k = 0; k < num_spans; ++k) {
    if (spans[k].first <= x && x <= spans[k].second) return true;
  }
  return false;
}

}  // namespace

bool FindADiff(const ImageView& image, const DetectorOptions& options,
               const std::vector<DetectedArea>& skip, RowCursor* cursor, cv::Point* seed,
               int* prefilter_rejects) {
  const ColorTable& table = image.table();
  const int step = options.step;
  const int r = image.r_offset(), b = image.b_offset();
  const int y = cursor->y;
  const uint8_t* row = image.Pixel(0, y);
  if (!cursor->sampled) {
    // The coarse table is within kCoarseErrorBound of the exact a*, so a true
    // rise above ADiffThresh shows at least this much in coarse values.
    const int coarse_thresh =
        static_cast<int>(std::floor(options.adiff_thresh)) - 2 * ColorTable::kCoarseErrorBound;
    const int count = (image.width() + step - 1) / step;
    thread_local std::vector<int32_t> coarse;
    thread_local std::vector<int> rises;
    if (coarse.size() < static_cast<size_t>(count)) {
      coarse.resize(count);
      rises.resize(count);
    }
    // The next sampled row, into the caches while this one is sampled: a
    // frame from a camera or another thread is not in the caches, and the
    // jump of several rows defeats the hardware's stream prefetch at each
    // row's start.
    const int next_y = y + options.sampled_row_step();
    if (next_y < image.height()) {
      const char* next = reinterpret_cast<const char*>(image.Pixel(0, next_y));
      const int bytes = 3 * image.width();
      for (int offset = 0; offset < bytes; offset += 64) __builtin_prefetch(next + offset);
    }
    cursor->num_rises =
        SampleRow({row, count, 3 * step, r, b, table.coarse_a_table(), coarse_thresh},
                  coarse.data(), rises.data());
    cursor->rises = rises.data();
    cursor->next = 0;
    cursor->sampled = true;
  }
  if (cursor->next >= cursor->num_rises) return false;
  const float adiff = static_cast<float>(options.adiff_thresh);
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
    const uint8_t* p = row + 3 * x;
    const uint8_t* q = p - 3 * step;
    const float exact_rise = table.A(p[r], p[1], p[b]) - table.A(q[r], q[1], q[b]);
    if (exact_rise > adiff) {
      *seed = cv::Point(x, y);
      return true;
    }
    ++*prefilter_rejects;
  }
  return false;
}

}  // namespace chromatag::internal
