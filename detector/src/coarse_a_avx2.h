// What the detector's AVX2 paths share: whether the CPU has AVX2, the
// coarse a* (ColorTable::CoarseA) of eight pixels at once, used by FindADiff
// and ImageView::FirstNotClearlyAbove, and the edge channels of eight pixels,
// used by the side profiles (ImageView::SampleLine, refine_corners.cc). Internal; CoarseA8 and
// MakeCoarseALookup only for functions compiled with
// __attribute__((target("avx2"))).
#ifndef CHROMATAG_DETECTOR_SRC_COARSE_A_AVX2_H_
#define CHROMATAG_DETECTOR_SRC_COARSE_A_AVX2_H_

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

// ImageView::Sample of the edge channel at eight points (pixel centres at
// integers), in the same arithmetic and order, without fused multiply-adds,
// so that the floats are the same. The caller guarantees that each point's
// four pixels lie inside the frame and that a 32-bit read at each does too.
__attribute__((target("avx2"))) inline __m256 BilinearEdgeChannel8(const uint8_t* data,
                                                                   __m256i step, __m256 px,
                                                                   __m256 py, bool gray,
                                                                   __m128i red_shift) {
  const __m256i three = _mm256_set1_epi32(3);
  const int* base = reinterpret_cast<const int*>(data);
  const __m256i x0 = _mm256_cvttps_epi32(px), y0 = _mm256_cvttps_epi32(py);
  const __m256 tx = _mm256_sub_ps(px, _mm256_cvtepi32_ps(x0));
  const __m256 ty = _mm256_sub_ps(py, _mm256_cvtepi32_ps(y0));
  const __m256i p = _mm256_add_epi32(_mm256_mullo_epi32(y0, step), _mm256_mullo_epi32(x0, three));
  const __m256i q = _mm256_add_epi32(p, step);
  const __m256i c00 = EdgeChannel8(_mm256_i32gather_epi32(base, p, 1), gray, red_shift);
  const __m256i c01 =
      EdgeChannel8(_mm256_i32gather_epi32(base, _mm256_add_epi32(p, three), 1), gray, red_shift);
  const __m256i c10 = EdgeChannel8(_mm256_i32gather_epi32(base, q, 1), gray, red_shift);
  const __m256i c11 =
      EdgeChannel8(_mm256_i32gather_epi32(base, _mm256_add_epi32(q, three), 1), gray, red_shift);
  const __m256 top = _mm256_add_ps(
      _mm256_cvtepi32_ps(c00), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c01, c00)), tx));
  const __m256 bottom = _mm256_add_ps(
      _mm256_cvtepi32_ps(c10), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c11, c10)), tx));
  return _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bottom, top), ty));
}

}  // namespace chromatag::internal

#endif
#endif  // CHROMATAG_DETECTOR_SRC_COARSE_A_AVX2_H_
