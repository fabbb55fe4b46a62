// Stage 1, FindADiff (paper section 4): the only stage that touches the whole
// frame, so it is the one that sets the speed on frames without tags.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <limits>
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
  int threshold;    // A rise (one step, or two from green) above this may seed.
  int step_thresh;  // Each of two steps rises above this (kTwoStepShare)...
  int green_limit;  // ...from a sample two back below this (kTwoStepGreenA)...
  int red_floor;    // ...to a sample above this (kTwoStepMinRedA).
};

// Whether sample i's coarse a* may seed (SeedsAt, each value within the
// table's error bound; RowSampler's thresholds allow for it).
inline bool CoarseRiseAt(const RowSampler& s, const int32_t* coarse, int i) {
  const int rise = coarse[i] - coarse[i - 1];
  if (rise > s.threshold) return true;
  return i >= 2 && coarse[i - 2] < s.green_limit && coarse[i] > s.red_floor &&
         coarse[i] - coarse[i - 2] > s.threshold && rise > s.step_thresh &&
         coarse[i - 1] - coarse[i - 2] > s.step_thresh;
}

void CoarseRowScalar(const RowSampler& s, int first, int32_t* coarse) {
  const uint8_t* p = s.row + static_cast<ptrdiff_t>(first) * s.pixel_step;
  for (int i = first; i < s.count; ++i, p += s.pixel_step)
    coarse[i] = s.table[((p[s.r] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[s.b] >> 3)];
}

int RisesScalar(const RowSampler& s, int first, int end, const int32_t* coarse, int* rises, int n) {
  for (int i = std::max(1, first); i < end; ++i) {
    if (CoarseRiseAt(s, coarse, i)) rises[n++] = i;
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
  // Sample 1 has no sample two before it: the scalar test.
  int n = RisesScalar(s, 1, std::min(2, s.count), coarse, rises, 0);
  const __m256i threshold = _mm256_set1_epi32(s.threshold);
  const __m256i step_thresh = _mm256_set1_epi32(s.step_thresh);
  const __m256i green_limit = _mm256_set1_epi32(s.green_limit);
  const __m256i red_floor = _mm256_set1_epi32(s.red_floor);
  int j = 2;
  for (; j + 8 <= s.count; j += 8) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j));
    const __m256i before = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j - 1));
    const __m256i two_before = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j - 2));
    const __m256i rise = _mm256_sub_epi32(a, before);
    const __m256i two_step = _mm256_and_si256(
        _mm256_and_si256(_mm256_and_si256(_mm256_cmpgt_epi32(green_limit, two_before),
                                          _mm256_cmpgt_epi32(a, red_floor)),
                         _mm256_cmpgt_epi32(_mm256_sub_epi32(a, two_before), threshold)),
        _mm256_and_si256(_mm256_cmpgt_epi32(rise, step_thresh),
                         _mm256_cmpgt_epi32(_mm256_sub_epi32(before, two_before), step_thresh)));
    const __m256i seeds = _mm256_or_si256(_mm256_cmpgt_epi32(rise, threshold), two_step);
    unsigned mask = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(seeds)));
    while (mask) {
      rises[n++] = j + __builtin_ctz(mask);
      mask &= mask - 1;
    }
  }
  return RisesScalar(s, j, s.count, coarse, rises, n);
}
#endif

#ifdef CHROMATAG_HAVE_AVX2_PATHS
#define CHROMATAG_AVX512_TARGET __attribute__((target("avx512f,avx512bw,avx512vbmi")))

// The computed a* (ColorTable::FastA) of 32 samples' channel words.
struct FastALanes {
  __m512i linear_low, linear_high;  // Entries 0-31 and 32-63 of each table.
  __m512i f_low, f_high, f_step_low, f_step_high;
  __m512i x_weight[3], y_weight[3];
};

CHROMATAG_AVX512_TARGET void LoadFastALanes(const ColorTable::FastATables& t, FastALanes* l) {
  l->linear_low = _mm512_load_si512(t.linear);
  l->linear_high = _mm512_load_si512(t.linear + 32);
  l->f_low = _mm512_load_si512(t.f);
  l->f_high = _mm512_load_si512(t.f + 32);
  l->f_step_low = _mm512_load_si512(t.f_step);
  l->f_step_high = _mm512_load_si512(t.f_step + 32);
  for (int c = 0; c < 3; ++c) {
    l->x_weight[c] = _mm512_set1_epi16(t.x_weight[c]);
    l->y_weight[c] = _mm512_set1_epi16(t.y_weight[c]);
  }
}

// f() of 32 values of t (ColorTable::FastA's f).
CHROMATAG_AVX512_TARGET inline __m512i FastF(const FastALanes& l, __m512i t) {
  t = _mm512_min_epu16(t, _mm512_set1_epi16(32767));
  const __mmask32 low = _mm512_cmplt_epu16_mask(t, _mm512_set1_epi16(4096));
  const __m512i index = _mm512_mask_blend_epi16(
      low, _mm512_add_epi16(_mm512_srli_epi16(t, 10), _mm512_set1_epi16(32)),
      _mm512_srli_epi16(t, 7));
  // The remainder at the top of a signed word: (t & 1023) << 5 or (t & 127) << 8.
  const __m512i fraction =
      _mm512_mask_blend_epi16(low, _mm512_srli_epi16(_mm512_slli_epi16(t, 6), 1),
                              _mm512_srli_epi16(_mm512_slli_epi16(t, 9), 1));
  return _mm512_add_epi16(
      _mm512_permutex2var_epi16(l.f_low, index, l.f_high),
      _mm512_mulhrs_epi16(_mm512_permutex2var_epi16(l.f_step_low, index, l.f_step_high), fraction));
}

// N = 4 only: 32 samples from six 64-byte loads, each sample's channel
// bytes moved into word lanes by byte permutes over pairs of loads (a
// sample's three bytes never straddle two loads), a* computed (FastA), and
// the rises found by comparing each lane with the one before. Returns the
// number of rises; `threshold` is in FastA's units.
CHROMATAG_AVX512_TARGET int SampleRowAvx512(const RowSampler& s, int row_bytes,
                                            const ColorTable::FastATables& tables, int threshold,
                                            int step_thresh, int green_limit, int red_floor,
                                            int* rises, int16_t* a_out = nullptr) {
  FastALanes lanes;
  LoadFastALanes(tables, &lanes);
  // Per pair of loads p (bytes 128 p to 128 p + 127 of the block), for each
  // sample j of the pair: its first two bytes into word j (low, high), and
  // its third into the low byte of word j.
  static const auto kPick = [] {
    struct {
      uint8_t first_two[3][64], third[3][64];
      __mmask64 two_bytes[3], low_bytes[3];
    } pick{};
    for (int j = 0; j < 32; ++j) {
      const int p = 12 * j / 128;
      const int at = 12 * j - 128 * p;
      pick.first_two[p][2 * j] = static_cast<uint8_t>(at);
      pick.first_two[p][2 * j + 1] = static_cast<uint8_t>(at + 1);
      pick.third[p][2 * j] = static_cast<uint8_t>(at + 2);
      pick.two_bytes[p] |= __mmask64{3} << (2 * j);
      pick.low_bytes[p] |= __mmask64{1} << (2 * j);
    }
    return pick;
  }();
  __m512i first_two[3], third[3];
  for (int p = 0; p < 3; ++p) {
    first_two[p] = _mm512_loadu_si512(kPick.first_two[p]);
    third[p] = _mm512_loadu_si512(kPick.third[p]);
  }
  alignas(64) static const int16_t kPrevious[32] = {63, 0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                                    10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
                                                    21, 22, 23, 24, 25, 26, 27, 28, 29, 30};
  alignas(64) static const int16_t kTwoBefore[32] = {62, 63, 0,  1,  2,  3,  4,  5,  6,  7,  8,
                                                     9,  10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
                                                     20, 21, 22, 23, 24, 25, 26, 27, 28, 29};
  const __m512i previous_index = _mm512_load_si512(kPrevious);
  const __m512i two_before_index = _mm512_load_si512(kTwoBefore);
  const __m512i rise_threshold = _mm512_set1_epi16(static_cast<int16_t>(threshold));
  const __m512i step_threshold = _mm512_set1_epi16(static_cast<int16_t>(step_thresh));
  const __m512i green = _mm512_set1_epi16(static_cast<int16_t>(green_limit));
  const __m512i red = _mm512_set1_epi16(static_cast<int16_t>(red_floor));
  __m512i previous = _mm512_setzero_si512();
  int n = 0;
  for (int i = 0; i < s.count; i += 32) {
    const uint8_t* block = s.row + 12 * static_cast<ptrdiff_t>(i);
    __m512i z[6];
    const int left = row_bytes - 12 * i;
    for (int q = 0; q < 6; ++q) {
      // The row's last block is read with a mask, never past the row.
      const int here = left - 64 * q;
      const __mmask64 mask = here >= 64  ? ~__mmask64{0}
                             : here <= 0 ? __mmask64{0}
                                         : (__mmask64{1} << here) - 1;
      z[q] = _mm512_maskz_loadu_epi8(mask, block + 64 * q);
    }
    const __m512i bytes01 = _mm512_or_si512(
        _mm512_or_si512(
            _mm512_maskz_permutex2var_epi8(kPick.two_bytes[0], z[0], first_two[0], z[1]),
            _mm512_maskz_permutex2var_epi8(kPick.two_bytes[1], z[2], first_two[1], z[3])),
        _mm512_maskz_permutex2var_epi8(kPick.two_bytes[2], z[4], first_two[2], z[5]));
    const __m512i bytes2 = _mm512_or_si512(
        _mm512_or_si512(_mm512_maskz_permutex2var_epi8(kPick.low_bytes[0], z[0], third[0], z[1]),
                        _mm512_maskz_permutex2var_epi8(kPick.low_bytes[1], z[2], third[1], z[3])),
        _mm512_maskz_permutex2var_epi8(kPick.low_bytes[2], z[4], third[2], z[5]));
    // The word permutes read the index's low six bits: a byte's top six are
    // its word shifted right by 2 (low byte) or 10 (high byte).
    auto linear_of = [&lanes](__m512i index) CHROMATAG_AVX512_TARGET {
      return _mm512_permutex2var_epi16(lanes.linear_low, index, lanes.linear_high);
    };
    const __m512i linear0 = linear_of(_mm512_srli_epi16(bytes01, 2));
    const __m512i linear2 = linear_of(_mm512_srli_epi16(bytes2, 2));
    __m512i linear[3];  // R, G, B
    linear[0] = s.r == 0 ? linear0 : linear2;
    linear[1] = linear_of(_mm512_srli_epi16(bytes01, 10));
    linear[2] = s.r == 0 ? linear2 : linear0;
    __m512i x = _mm512_mulhrs_epi16(linear[0], lanes.x_weight[0]);
    __m512i y = _mm512_mulhrs_epi16(linear[0], lanes.y_weight[0]);
    for (int c = 1; c < 3; ++c) {
      x = _mm512_add_epi16(x, _mm512_mulhrs_epi16(linear[c], lanes.x_weight[c]));
      y = _mm512_add_epi16(y, _mm512_mulhrs_epi16(linear[c], lanes.y_weight[c]));
    }
    const __m512i a = _mm512_sub_epi16(FastF(lanes, x), FastF(lanes, y));
    if (a_out) _mm512_storeu_si512(a_out + i, a);  // ComputedARow (tests).
    const __m512i before = _mm512_permutex2var_epi16(a, previous_index, previous);
    const __m512i two_before = _mm512_permutex2var_epi16(a, two_before_index, previous);
    const __m512i rise = _mm512_subs_epi16(a, before);
    uint32_t two_step =
        _mm512_cmplt_epi16_mask(two_before, green) & _mm512_cmpgt_epi16_mask(a, red) &
        _mm512_cmpgt_epi16_mask(_mm512_subs_epi16(a, two_before), rise_threshold) &
        _mm512_cmpgt_epi16_mask(rise, step_threshold) &
        _mm512_cmpgt_epi16_mask(_mm512_subs_epi16(before, two_before), step_threshold);
    if (i == 0) two_step &= ~3u;  // The first two samples have none two before them.
    uint32_t mask = _mm512_cmpgt_epi16_mask(rise, rise_threshold) | two_step;
    if (i == 0) mask &= ~1u;  // The first sample has none before it.
    if (s.count - i < 32) mask &= (1u << (s.count - i)) - 1;
    while (mask) {
      rises[n++] = i + __builtin_ctz(mask);
      mask &= mask - 1;
    }
    previous = a;
  }
  return n;
}
#endif

}  // namespace

int ComputedARiseThreshold(double adiff_thresh) {
  const double units =
      std::floor((adiff_thresh - 2 * ColorTable::kFastAErrorBound) * ColorTable::kFastAUnitsPerA);
  return static_cast<int>(std::clamp(units, -32768.0, 32767.0));
}

int ComputedATwoStepRedFloor() {
  return static_cast<int>(
      std::floor((kTwoStepMinRedA - ColorTable::kFastAErrorBound) * ColorTable::kFastAUnitsPerA));
}

int ComputedAGreenLimit() {
  return static_cast<int>(
      std::ceil((kTwoStepGreenA + ColorTable::kFastAErrorBound) * ColorTable::kFastAUnitsPerA));
}

bool RowScanPathAvailable(RowScanPath path) {
  switch (path) {
    case RowScanPath::kComputedAAvx512:
#ifdef CHROMATAG_HAVE_AVX2_PATHS
      return CpuHasAvx512Vbmi();
#else
      return false;
#endif
    case RowScanPath::kCoarseAvx2:
#ifdef CHROMATAG_HAVE_AVX2_PATHS
      return CpuHasAvx2();
#else
      return false;
#endif
    default:
      return true;
  }
}

bool ComputedARow(const ImageView& image, const DetectorOptions& options, int y,
                  std::vector<int16_t>* a) {
#ifdef CHROMATAG_HAVE_AVX2_PATHS
  if (!RowScanComputesA(options)) return false;
  const int count = (image.width() + 3) / 4;
  const RowSampler sampler{image.Pixel(0, y), count,   12,      image.r_offset(), image.b_offset(),
                           nullptr,           INT_MAX, INT_MAX, INT_MIN,          INT_MAX};
  std::vector<int> rises(count);
  a->assign((count + 31) / 32 * 32, 0);
  // The highest threshold: no rise is listed, only the values stored.
  SampleRowAvx512(sampler, 3 * image.width(), image.table().fast_a_tables(), 32767, 32767, -32768,
                  32767, rises.data(), a->data());
  a->resize(count);
  return true;
#else
  (void)image, (void)options, (void)y, (void)a;
  return false;
#endif
}

bool RowScanComputesA(const DetectorOptions& options) {
  return options.step == 4 && RowScanPathAvailable(RowScanPath::kComputedAAvx512);
}

int ScanRow(const ImageView& image, const DetectorOptions& options, int y, RowScanPath path,
            int32_t* coarse, int* rises) {
  const int step = options.step;
  const int count = (image.width() + step - 1) / step;
  // The coarse table is within kCoarseErrorBound of the accurate a*, so a
  // true rise above ADiffThresh shows at least this much in coarse values.
  const int coarse_thresh =
      static_cast<int>(std::floor(options.adiff_thresh)) - 2 * ColorTable::kCoarseErrorBound;
  const int coarse_step_thresh =
      static_cast<int>(std::floor(kTwoStepShare * options.adiff_thresh)) -
      2 * ColorTable::kCoarseErrorBound;
  // Without two_step_rises, no sample counts as green.
  const int coarse_green = options.two_step_rises ? static_cast<int>(std::ceil(kTwoStepGreenA)) +
                                                        ColorTable::kCoarseErrorBound
                                                  : INT_MIN;
  const int coarse_red =
      static_cast<int>(std::floor(kTwoStepMinRedA)) - ColorTable::kCoarseErrorBound - 1;
  const ColorTable& table = image.table();
  const RowSampler sampler{
      image.Pixel(0, y),      count,         3 * step,           image.r_offset(), image.b_offset(),
      table.coarse_a_table(), coarse_thresh, coarse_step_thresh, coarse_green,     coarse_red};
  if (path == RowScanPath::kWidest) {
    path = RowScanComputesA(options)                        ? RowScanPath::kComputedAAvx512
           : RowScanPathAvailable(RowScanPath::kCoarseAvx2) ? RowScanPath::kCoarseAvx2
                                                            : RowScanPath::kCoarseScalar;
  }
#ifdef CHROMATAG_HAVE_AVX2_PATHS
  if (path == RowScanPath::kComputedAAvx512 && step == 4 && CpuHasAvx512Vbmi()) {
    return SampleRowAvx512(sampler, 3 * image.width(), table.fast_a_tables(),
                           ComputedARiseThreshold(options.adiff_thresh),
                           ComputedARiseThreshold(kTwoStepShare * options.adiff_thresh),
                           options.two_step_rises ? ComputedAGreenLimit() : -32768,
                           ComputedATwoStepRedFloor(), rises);
  }
  if (path != RowScanPath::kCoarseScalar && CpuHasAvx2()) {
    return SampleRowAvx2(sampler, coarse, rises);
  }
#endif
  CoarseRowScalar(sampler, 0, coarse);
  return RisesScalar(sampler, 1, count, coarse, rises, 0);
}

namespace {

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
    if (RowScanComputesA(options)) {
      // The coarse table, for the ring scans of this frame's seeds, spread
      // over the sampled rows (Detect did not stream it).
      const int row_step = options.sampled_row_step();
      const int rows = (image.height() + row_step - 1) / row_step;
      const int per_row = (table.coarse_lines() + rows - 1) / rows;
      table.PrefetchCoarseLines(y / row_step * per_row, per_row);
    }
    cursor->num_rises =
        ScanRow(image, options, y, RowScanPath::kWidest, coarse.data(), rises.data());
    cursor->rises = rises.data();
    cursor->next = 0;
    cursor->sampled = true;
  }
  if (cursor->next >= cursor->num_rises) return false;
  constexpr float kNoSample = std::numeric_limits<float>::quiet_NaN();
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
    // The sample two back, for the rise in two steps (SeedsAt); none past an
    // accepted area either.
    const bool has_two =
        options.two_step_rises && i >= 2 && !(num_spans && InSpans(spans, num_spans, x - 2 * step));
    const float two_before =
        has_two ? table.A(q[r - 3 * step], q[1 - 3 * step], q[b - 3 * step]) : kNoSample;
    // L* only where the rise in two steps needs it.
    const LabF lab = two_before < kTwoStepGreenA ? table.Lab(p[r], p[1], p[b])
                                                 : LabF{0.f, table.A(p[r], p[1], p[b]), 0.f};
    if (SeedsAt(options, lab, table.A(q[r], q[1], q[b]), two_before)) {
      *seed = cv::Point(x, y);
      return true;
    }
    ++*prefilter_rejects;
  }
  return false;
}

}  // namespace chromatag::internal
