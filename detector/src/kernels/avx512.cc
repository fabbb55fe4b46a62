// The AVX-512 kernels (avx512.h, kernels.h): FindADiff's row scan with a*
// computed in 16-bit lanes (ColorTable::FastA), 32 samples at a time. Each
// function is compiled for AVX-512 F, BW and VBMI alone (CHROMATAG_AVX512),
// so that a portable build runs anywhere.
#include "kernels/avx512.h"

#include "kernels/kernels.h"

#ifdef CHROMATAG_HAVE_X86_KERNELS

#include <immintrin.h>

#include <algorithm>
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

// Per pair of loads p (bytes 128 p to 128 p + 127 of a block of 32
// samples), for each sample j of the pair: its first two bytes into word j
// (low, high), and its third into the low byte of word j.
struct SamplePicks {
  uint8_t first_two[3][64], third[3][64];
  __mmask64 two_bytes[3], low_bytes[3];
};
const SamplePicks& Picks() {
  static const SamplePicks kPicks = [] {
    SamplePicks pick{};
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
  return kPicks;
}

// The byte permutes of SamplePicks, and the lanes of a block's samples
// that hold each one's sample before it and two before it (from the
// previous block in the lanes past its end).
struct RowLanes {
  __m512i first_two[3], third[3];
  __m512i previous_index, two_before_index;
};
CHROMATAG_AVX512 void LoadRowLanes(const SamplePicks& pick, RowLanes* lanes) {
  for (int p = 0; p < 3; ++p) {
    lanes->first_two[p] = _mm512_loadu_si512(pick.first_two[p]);
    lanes->third[p] = _mm512_loadu_si512(pick.third[p]);
  }
  alignas(64) static const int16_t kPrevious[32] = {63, 0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                                    10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
                                                    21, 22, 23, 24, 25, 26, 27, 28, 29, 30};
  alignas(64) static const int16_t kTwoBefore[32] = {62, 63, 0,  1,  2,  3,  4,  5,  6,  7,  8,
                                                     9,  10, 11, 12, 13, 14, 15, 16, 17, 18, 19,
                                                     20, 21, 22, 23, 24, 25, 26, 27, 28, 29};
  lanes->previous_index = _mm512_load_si512(kPrevious);
  lanes->two_before_index = _mm512_load_si512(kTwoBefore);
}

// The 384 bytes of the 32 samples from sample i on, as six 64-byte loads;
// the row's last block is read with a mask, never past the row.
CHROMATAG_AVX512 inline void LoadBlock(const RowSampler& s, int i, __m512i* z) {
  const uint8_t* block = s.row + 12 * static_cast<ptrdiff_t>(i);
  const int left = s.row_bytes - 12 * i;
  for (int q = 0; q < 6; ++q) {
    const int here = left - 64 * q;
    const __mmask64 mask = here >= 64  ? ~__mmask64{0}
                           : here <= 0 ? __mmask64{0}
                                       : (__mmask64{1} << here) - 1;
    z[q] = _mm512_maskz_loadu_epi8(mask, block + 64 * q);
  }
}

// A block's samples' channel bytes in word lanes: the first two bytes of
// each (low, high) into *bytes01, the third into the low byte of *bytes2
// (a sample's three bytes never straddle two loads).
CHROMATAG_AVX512 inline void PickChannelBytes(const SamplePicks& pick, const RowLanes& lanes,
                                              const __m512i* z, __m512i* bytes01, __m512i* bytes2) {
  *bytes01 = _mm512_or_si512(
      _mm512_or_si512(
          _mm512_maskz_permutex2var_epi8(pick.two_bytes[0], z[0], lanes.first_two[0], z[1]),
          _mm512_maskz_permutex2var_epi8(pick.two_bytes[1], z[2], lanes.first_two[1], z[3])),
      _mm512_maskz_permutex2var_epi8(pick.two_bytes[2], z[4], lanes.first_two[2], z[5]));
  *bytes2 = _mm512_or_si512(
      _mm512_or_si512(
          _mm512_maskz_permutex2var_epi8(pick.low_bytes[0], z[0], lanes.third[0], z[1]),
          _mm512_maskz_permutex2var_epi8(pick.low_bytes[1], z[2], lanes.third[1], z[3])),
      _mm512_maskz_permutex2var_epi8(pick.low_bytes[2], z[4], lanes.third[2], z[5]));
}

// The linear light of 32 channel values: the word permutes read the
// index's low six bits, so `index` may be a byte's word shifted right by 2
// (low byte) or 10 (high byte), its top six bits.
CHROMATAG_AVX512 inline __m512i LinearOf(const FastALanes& l, __m512i index) {
  return _mm512_permutex2var_epi16(l.linear_low, index, l.linear_high);
}

// The computed a* (ColorTable::FastA) of a block's 32 samples, and their
// luminance (ColorTable::FastY) in *luminance.
CHROMATAG_AVX512 inline __m512i ComputedA32(const FastALanes& l, __m512i bytes01, __m512i bytes2,
                                            int r_offset, __m512i* luminance) {
  const __m512i linear0 = LinearOf(l, _mm512_srli_epi16(bytes01, 2));
  const __m512i linear2 = LinearOf(l, _mm512_srli_epi16(bytes2, 2));
  __m512i linear[3];  // R, G, B
  linear[0] = r_offset == 0 ? linear0 : linear2;
  linear[1] = LinearOf(l, _mm512_srli_epi16(bytes01, 10));
  linear[2] = r_offset == 0 ? linear2 : linear0;
  __m512i x = _mm512_mulhrs_epi16(linear[0], l.x_weight[0]);
  __m512i y = _mm512_mulhrs_epi16(linear[0], l.y_weight[0]);
  for (int c = 1; c < 3; ++c) {
    x = _mm512_add_epi16(x, _mm512_mulhrs_epi16(linear[c], l.x_weight[c]));
    y = _mm512_add_epi16(y, _mm512_mulhrs_epi16(linear[c], l.y_weight[c]));
  }
  *luminance = y;
  return _mm512_sub_epi16(FastF(l, x), FastF(l, y));
}

// The sampler's thresholds in every lane.
struct RiseThresholds {
  __m512i rise, step, green, red, dim_two_step, dim_y;
};
CHROMATAG_AVX512 inline RiseThresholds MakeRiseThresholds(const RowSampler& s) {
  return {_mm512_set1_epi16(static_cast<int16_t>(s.threshold)),
          _mm512_set1_epi16(static_cast<int16_t>(s.step_thresh)),
          _mm512_set1_epi16(static_cast<int16_t>(s.green_limit)),
          _mm512_set1_epi16(static_cast<int16_t>(s.red_floor)),
          _mm512_set1_epi16(static_cast<int16_t>(s.dim_two_step_thresh)),
          _mm512_set1_epi16(static_cast<int16_t>(std::clamp(s.dim_y_limit, 0, 65535)))};
}

// The samples of the block from sample i on (a* `a`, luminance `luminance`,
// the previous block's a* `previous`) that may seed, as bits, the row's
// first two samples and those past its end left out.
CHROMATAG_AVX512 inline uint32_t RisesIn32(const RowSampler& s, const RowLanes& lanes,
                                           const RiseThresholds& t, int i, __m512i a,
                                           __m512i luminance, __m512i previous) {
  const __m512i before = _mm512_permutex2var_epi16(a, lanes.previous_index, previous);
  const __m512i two_before = _mm512_permutex2var_epi16(a, lanes.two_before_index, previous);
  const __m512i rise = _mm512_subs_epi16(a, before);
  const __m512i two_step_rise = _mm512_subs_epi16(a, two_before);
  const uint32_t total = _mm512_cmpgt_epi16_mask(two_step_rise, t.rise) |
                         (_mm512_cmpgt_epi16_mask(two_step_rise, t.dim_two_step) &
                          _mm512_cmplt_epu16_mask(luminance, t.dim_y));
  uint32_t two_step = _mm512_cmplt_epi16_mask(two_before, t.green) &
                      _mm512_cmpgt_epi16_mask(a, t.red) & total &
                      _mm512_cmpgt_epi16_mask(rise, t.step) &
                      _mm512_cmpgt_epi16_mask(_mm512_subs_epi16(before, two_before), t.step);
  if (i == 0) two_step &= ~3u;  // The first two samples have none two before them.
  uint32_t mask = _mm512_cmpgt_epi16_mask(rise, t.rise) | two_step;
  if (i == 0) mask &= ~1u;  // The first sample has none before it.
  if (s.count - i < 32) mask &= (1u << (s.count - i)) - 1;
  return mask;
}

// N = 4 only: 32 samples from six 64-byte loads (LoadBlock), each sample's
// channel bytes moved into word lanes by byte permutes over pairs of loads
// (PickChannelBytes), a* computed (FastA), and the rises found by comparing
// each lane with the one before (RisesIn32). Returns the number of rises;
// with kStoreA, the a* of the samples goes to a_out too.
template <bool kStoreA>
CHROMATAG_AVX512 int SampleRow(const RowSampler& s, const ColorTable::FastATables& tables,
                               int* rises, int16_t* a_out) {
  FastALanes fast_a;
  LoadFastALanes(tables, &fast_a);
  const SamplePicks& pick = Picks();
  RowLanes lanes;
  LoadRowLanes(pick, &lanes);
  const RiseThresholds thresholds = MakeRiseThresholds(s);
  __m512i previous = _mm512_setzero_si512();
  int n = 0;
  for (int i = 0; i < s.count; i += 32) {
    __m512i z[6], bytes01, bytes2;
    LoadBlock(s, i, z);
    PickChannelBytes(pick, lanes, z, &bytes01, &bytes2);
    __m512i luminance;
    const __m512i a = ComputedA32(fast_a, bytes01, bytes2, s.r, &luminance);
    if (kStoreA) _mm512_storeu_si512(a_out + i, a);
    for (uint32_t mask = RisesIn32(s, lanes, thresholds, i, a, luminance, previous); mask;
         mask &= mask - 1) {
      rises[n++] = i + __builtin_ctz(mask);
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
  all.threshold = all.step_thresh = all.red_floor = all.dim_two_step_thresh = 32767;
  all.green_limit = -32768;
  std::vector<int> rises(s.count);
  SampleRow<true>(all, tables, rises.data(), a);
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_HAVE_X86_KERNELS
