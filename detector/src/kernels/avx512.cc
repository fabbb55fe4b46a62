// The AVX-512 kernels (avx512.h, kernels.h): FindADiff's row scan with a*
// computed in 16-bit lanes (ColorTable::FastA), 32 samples at a time. Each
// function is compiled for AVX-512 F, BW and VBMI alone (CHROMATAG_AVX512),
// so that a portable build runs anywhere.
#include "kernels/avx512.h"

#include "kernels/kernels.h"

#ifdef CHROMATAG_HAVE_X86_KERNELS

#include <immintrin.h>

#include <cstdint>
#include <vector>

namespace chromatag::internal {
namespace {

// The computed a* (ColorTable::FastA) of 32 samples' channel words.
struct FastALanes {
  __m512i linear_low, linear_high;  // Entries 0-31 and 32-63 of each table.
  __m512i f_low, f_high, f_step_low, f_step_high;
  __m512i x_weight[3], y_weight[3];
};

CHROMATAG_AVX512 void LoadFastALanes(const ColorTable::FastATables& t, FastALanes* l) {
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
CHROMATAG_AVX512 inline __m512i FastF(const FastALanes& l, __m512i t) {
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
// number of rises; with kStoreA, the a* of the samples goes to a_out too.
template <bool kStoreA>
CHROMATAG_AVX512 int SampleRow(const RowSampler& s, const ColorTable::FastATables& tables,
                               int* rises, int16_t* a_out) {
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
  const __m512i rise_threshold = _mm512_set1_epi16(static_cast<int16_t>(s.threshold));
  const __m512i step_threshold = _mm512_set1_epi16(static_cast<int16_t>(s.step_thresh));
  const __m512i green = _mm512_set1_epi16(static_cast<int16_t>(s.green_limit));
  const __m512i red = _mm512_set1_epi16(static_cast<int16_t>(s.red_floor));
  __m512i previous = _mm512_setzero_si512();
  int n = 0;
  for (int i = 0; i < s.count; i += 32) {
    const uint8_t* block = s.row + 12 * static_cast<ptrdiff_t>(i);
    __m512i z[6];
    const int left = s.row_bytes - 12 * i;
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
    auto linear_of = [&lanes](__m512i index) CHROMATAG_AVX512 {
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
    if (kStoreA) _mm512_storeu_si512(a_out + i, a);
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

}  // namespace

CHROMATAG_AVX512 int ScanRowComputedAAvx512(const RowSampler& s,
                                            const ColorTable::FastATables& tables, int* rises) {
  return SampleRow<false>(s, tables, rises, nullptr);
}

CHROMATAG_AVX512 void ComputedARowAvx512(const RowSampler& s, const ColorTable::FastATables& tables,
                                         int16_t* a) {
  // The highest thresholds: no rise is listed, only the values stored.
  RowSampler all = s;
  all.threshold = all.step_thresh = all.red_floor = 32767;
  all.green_limit = -32768;
  std::vector<int> rises(s.count);
  SampleRow<true>(all, tables, rises.data(), a);
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_HAVE_X86_KERNELS
