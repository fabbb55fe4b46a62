// The pieces the detector's AVX2 paths share: whether the CPU has AVX2,
// RoundToInt of eight floats, the coarse a* (ColorTable::CoarseA) of eight
// pixels (FindADiff, ImageView::FirstNotClearlyAbove), and the bilinear edge
// channel at eight points (ImageView::SampleLine, the side profiles of
// refine_corners.cc). Internal; everything but CpuHasAvx2 only for functions
// compiled with __attribute__((target("avx2"))).
#ifndef CHROMATAG_DETECTOR_SRC_AVX2_KERNELS_H_
#define CHROMATAG_DETECTOR_SRC_AVX2_KERNELS_H_

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define CHROMATAG_HAVE_AVX2_PATHS 1

#include <immintrin.h>

#include <cstdint>

namespace chromatag::internal {

// Whether the running CPU has AVX2 (the paths are chosen at run time, so
// that a portable build runs anywhere).
inline bool CpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// Whether the running CPU has the AVX-512 subsets of FindADiff's widest path
// (byte and word lanes, and byte permutes).
inline bool CpuHasAvx512Vbmi() {
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                          __builtin_cpu_supports("avx512vbmi");
  return has;
}

// RoundToInt (image_view.h) of eight floats: nearest, halves up.
__attribute__((target("avx2"))) inline __m256i RoundToInt8(__m256 v) {
  const __m256 shifted = _mm256_add_ps(v, _mm256_set1_ps(0.5f));
  const __m256i truncated = _mm256_cvttps_epi32(shifted);
  // Truncation rounds towards zero; one less where that rounded up.
  return _mm256_add_epi32(truncated, _mm256_castps_si256(_mm256_cmp_ps(
                                         shifted, _mm256_cvtepi32_ps(truncated), _CMP_LT_OQ)));
}

// The shifts that bring each channel's top five bits down in a pixel's
// 32-bit word (its three bytes first, in either order), and the table.
struct CoarseALookup {
  __m128i shift_r, shift_g, shift_b;
  const int* table;  // ColorTable::coarse_a_table(), padded for 32-bit reads.
};

__attribute__((target("avx2"))) inline CoarseALookup MakeCoarseALookup(int r_offset,
                                                                       const int8_t* table) {
  return {_mm_cvtsi32_si128(8 * r_offset + 3), _mm_cvtsi32_si128(8 + 3),
          _mm_cvtsi32_si128(8 * (2 - r_offset) + 3), reinterpret_cast<const int*>(table)};
}

// `words`: eight pixels' bytes as 32-bit lanes (the fourth byte ignored).
// Returns their coarse a*, sign-extended to 32 bits.
__attribute__((target("avx2"))) inline __m256i CoarseA8(const CoarseALookup& lookup,
                                                        __m256i words) {
  const __m256i mask5 = _mm256_set1_epi32(0x1F);
  const __m256i r5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_r), mask5);
  const __m256i g5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_g), mask5);
  const __m256i b5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_b), mask5);
  const __m256i index =
      _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi32(r5, 10), _mm256_slli_epi32(g5, 5)), b5);
  const __m256i entries = _mm256_i32gather_epi32(lookup.table, index, 1);
  return _mm256_srai_epi32(_mm256_slli_epi32(entries, 24), 24);
}

// `words`: eight pixels' bytes as 32-bit lanes (the fourth byte ignored).
// Returns R + G + B (`gray`) or R - G of each (ChannelWeights kGray and
// kRedMinusGreen); `red_shift` is 8 times the red byte's offset.
__attribute__((target("avx2"))) inline __m256i EdgeChannel8(__m256i words, bool gray,
                                                            __m128i red_shift) {
  const __m256i byte = _mm256_set1_epi32(0xFF);
  const __m256i g = _mm256_and_si256(_mm256_srli_epi32(words, 8), byte);
  if (gray) {
    return _mm256_add_epi32(_mm256_add_epi32(_mm256_and_si256(words, byte), g),
                            _mm256_and_si256(_mm256_srli_epi32(words, 16), byte));
  }
  return _mm256_sub_epi32(_mm256_and_si256(_mm256_srl_epi32(words, red_shift), byte), g);
}

// The low 32 bits of x's 64-bit words and of y's: x0 x1 y0 y1 | x2 x3 y2 y3.
__attribute__((target("avx2"))) inline __m256i LowHalves(__m256i x, __m256i y) {
  return _mm256_castps_si256(
      _mm256_shuffle_ps(_mm256_castsi256_ps(x), _mm256_castsi256_ps(y), 0x88));
}

// The bytes at `offsets` (eight 32-bit lanes) and the three bytes after
// them's, as two sets of 32-bit lanes: each lane's pixel and the next pixel
// in its row. Two 64-bit gathers of four, instead of two 32-bit gathers of
// eight. Each read reaches two bytes past the next pixel.
__attribute__((target("avx2"))) inline void GatherPixelPairs8(const uint8_t* data, __m256i offsets,
                                                              __m256i* left, __m256i* right) {
  // Lanes 0, 1, 4, 5 and 2, 3, 6, 7: _mm256_shuffle_ps(a, b, 0x88) then
  // puts the low halves of a's and b's 64-bit words back in lane order.
  const __m128i first = _mm256_castsi256_si128(
      _mm256_permutevar8x32_epi32(offsets, _mm256_setr_epi32(0, 1, 4, 5, 0, 0, 0, 0)));
  const __m128i second = _mm256_castsi256_si128(
      _mm256_permutevar8x32_epi32(offsets, _mm256_setr_epi32(2, 3, 6, 7, 0, 0, 0, 0)));
  const auto* base = reinterpret_cast<const long long*>(data);
  const __m256i a = _mm256_i32gather_epi64(base, first, 1);
  const __m256i b = _mm256_i32gather_epi64(base, second, 1);
  *left = LowHalves(a, b);
  *right = LowHalves(_mm256_srli_epi64(a, 24), _mm256_srli_epi64(b, 24));
}

// ImageView::Sample of the edge channel at eight points (pixel centres at
// integers), in the same arithmetic and order, without fused multiply-adds,
// so that the floats are the same. The caller guarantees that each point's
// four pixels lie inside the frame and that a read of two bytes past the
// lower right one does too.
__attribute__((target("avx2"))) inline __m256 BilinearEdgeChannel8(const uint8_t* data,
                                                                   __m256i step, __m256 px,
                                                                   __m256 py, bool gray,
                                                                   __m128i red_shift) {
  const __m256i three = _mm256_set1_epi32(3);
  const __m256i x0 = _mm256_cvttps_epi32(px), y0 = _mm256_cvttps_epi32(py);
  const __m256 tx = _mm256_sub_ps(px, _mm256_cvtepi32_ps(x0));
  const __m256 ty = _mm256_sub_ps(py, _mm256_cvtepi32_ps(y0));
  const __m256i p = _mm256_add_epi32(_mm256_mullo_epi32(y0, step), _mm256_mullo_epi32(x0, three));
  __m256i w00, w01, w10, w11;
  GatherPixelPairs8(data, p, &w00, &w01);
  GatherPixelPairs8(data, _mm256_add_epi32(p, step), &w10, &w11);
  const __m256i c00 = EdgeChannel8(w00, gray, red_shift);
  const __m256i c01 = EdgeChannel8(w01, gray, red_shift);
  const __m256i c10 = EdgeChannel8(w10, gray, red_shift);
  const __m256i c11 = EdgeChannel8(w11, gray, red_shift);
  const __m256 top = _mm256_add_ps(
      _mm256_cvtepi32_ps(c00), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c01, c00)), tx));
  const __m256 bottom = _mm256_add_ps(
      _mm256_cvtepi32_ps(c10), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c11, c10)), tx));
  return _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bottom, top), ty));
}

}  // namespace chromatag::internal

#endif
#endif  // CHROMATAG_DETECTOR_SRC_AVX2_KERNELS_H_
